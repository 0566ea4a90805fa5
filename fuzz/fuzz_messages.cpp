// Fuzz target of the messages between ranks (distributed/protocol.h, scene_codec.h):
// every decoder must return a message or throw WireError / InputError for any bytes, and
// a message it returns, encoded, must survive a further round trip unchanged.
//
// Input: byte 0 picks the message kind; the rest patches a valid message of that kind
// (pairs of offset, value bytes), its last byte sets a truncation, or, after a 0xff
// marker, replaces the message outright. Starting from valid messages lets the fuzzer
// reach the checks deep inside them without a seed corpus.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/error.h"
#include "distributed/pixel_codec.h"
#include "distributed/protocol.h"
#include "distributed/scene_codec.h"
#include "distributed/wire.h"
#include "scene/builders.h"

namespace {

using namespace multiray;
using namespace multiray::remote;

std::vector<uint8_t> valid(uint8_t kind) {
  switch (kind % 6) {
    case 0: {
      FrameMessage m;
      ViewSetup v;
      v.width = 4, v.height = 2;
      m.views = {v};
      m.spp_maps = {std::vector<uint8_t>(8, 2)};
      return encode(m);
    }
    case 1:
      return encode(WorkMessage{
          3, true, {0, 1}, {WorkItem{Rect{0, 0, 2, 2}, 0}, WorkItem{Rect{2, 0, 4, 2}, 0}}});
    case 2: {
      ResultMessage m;
      ItemResult it;
      it.report.item = WorkItem{Rect{0, 0, 2, 1}, 0};
      it.pixels = {{1, 2, 3}, {4, 5, 6}};
      m.items = {it};
      // Every --result-encoding this build has, by the kind byte's higher values.
      m.encoding = ResultEncoding(kind / 6 % kResultEncodings);
      if (uses_zstd(m.encoding) && !zstd_available()) m.encoding = ResultEncoding::float32;
      m.local = {{1, 1}};
      return encode(m);
    }
    case 3: {
      HelloMessage h;
      DeviceInfo d;
      d.caps.kernels = {"path"};
      h.devices = {d};
      return encode(h);
    }
    case 4:
      return encode(FailureMessage{1, "x"});
    default:
      return encode_scene(make_cornell_box());
  }
}

// `bytes` decoded as `kind` and encoded again (throws as the decoder does).
std::vector<uint8_t> round_trip(uint8_t kind, const std::vector<uint8_t>& bytes) {
  switch (kind % 6) {
    case 0:
      return encode(decode_frame(bytes));
    case 1:
      return encode(decode_work(bytes));
    case 2:
      return encode(decode_result(bytes, ResultBounds{64, 64, 2}));
    case 3:
      return encode(decode_hello(bytes));
    case 4:
      return encode(decode_failure(bytes));
    default:
      return encode_scene(decode_scene(bytes));
  }
}

// Decodes `bytes` as `kind`; what a decoder accepted, once encoded, must decode and encode
// to the same bytes again (the first trip may normalise: a flag byte of 2 reads as true and
// is written as 1).
void decode(uint8_t kind, const std::vector<uint8_t>& bytes) {
  const std::vector<uint8_t> once = round_trip(kind, bytes);
  if (round_trip(kind, once) != once) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t kind = data[0];
  std::vector<uint8_t> bytes;
  if (size >= 2 && data[1] == 0xff) {
    bytes.assign(data + 2, data + size);
  } else {
    bytes = valid(kind);
    size_t i = 1;
    for (; i + 1 < size; i += 2) bytes[data[i] % bytes.size()] = data[i + 1];
    if (i < size) bytes.resize(bytes.size() - data[i] % (bytes.size() + 1));
  }
  try {
    decode(kind, bytes);
  } catch (const WireError&) {
  } catch (const InputError&) {
  }
  return 0;
}
