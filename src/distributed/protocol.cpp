#include "distributed/protocol.h"

#include <cmath>
#include <iterator>

#include "distributed/pixel_codec.h"
#include "distributed/wire.h"
#include "util/aggregate.h"

namespace multiray::remote {

namespace {

constexpr int kMaxSide = 1 << 16;  // no image side beyond this travels

void put_info(ByteWriter& w, const DeviceInfo& d) {
  w.put_string(d.type), w.put_string(d.name), w.put_string(d.spec);
  w.put(int32_t(d.threads)), w.put(d.emulated_speed), w.put(d.cpu_quota);
  w.put(uint64_t(d.caps.kernels.size()));
  for (const auto& k : d.caps.kernels) w.put_string(k);
  w.put(uint64_t(d.caps.sampling.size()));
  for (const auto& s : d.caps.sampling) w.put_string(s);
  w.put_string(d.caps.representation);
}

DeviceInfo get_info(ByteReader& r) {
  DeviceInfo d;
  d.type = r.get_string(), d.name = r.get_string(), d.spec = r.get_string();
  d.threads = r.get<int32_t>(), d.emulated_speed = r.get<double>(), d.cpu_quota = r.get<double>();
  for (uint64_t n = r.count(8); n > 0; --n) d.caps.kernels.push_back(r.get_string());
  for (uint64_t n = r.count(8); n > 0; --n) d.caps.sampling.push_back(r.get_string());
  d.caps.representation = r.get_string();
  return d;
}

void put_item(ByteWriter& w, const WorkItem& it) {
  w.put(int32_t(it.rect.x0)), w.put(int32_t(it.rect.y0));
  w.put(int32_t(it.rect.x1)), w.put(int32_t(it.rect.y1)), w.put(int32_t(it.view));
}

WorkItem get_item(ByteReader& r) {
  WorkItem it;
  it.rect.x0 = r.get<int32_t>(), it.rect.y0 = r.get<int32_t>();
  it.rect.x1 = r.get<int32_t>(), it.rect.y1 = r.get<int32_t>(), it.view = r.get<int32_t>();
  if (it.rect.x0 < 0 || it.rect.y0 < 0 || it.rect.x1 > kMaxSide || it.rect.y1 > kMaxSide ||
      it.rect.x1 < it.rect.x0 || it.rect.y1 < it.rect.y0 || it.view < 0)
    throw WireError("work item out of range");
  return it;
}

// RenderSettings on the wire: the fields for_each_sent_setting lists, in its order.
static_assert(aggregate_field_count<RenderSettings>() ==
                  kSentSettings + std::size(kRankLocalSettings),
              "a RenderSettings field is neither sent nor rank-local: add it to "
              "for_each_sent_setting or kRankLocalSettings (render/render_settings.h)");

// The Frame message field by field (encode/decode below; run settings beside
// RenderSettings, such as --result-encoding, travel here): a new field must be written,
// read, and shown to travel in tests/mpi (result_encoding_test.cpp checks `results`).
static_assert(aggregate_field_count<FrameMessage>() == 5,
              "a FrameMessage field is not on the wire: encode and decode it");

struct SettingWriter {
  ByteWriter& w;
  void operator()(const char*, int v) const { w.put(int32_t(v)); }
  void operator()(const char*, uint64_t v) const { w.put(v); }
  void operator()(const char*, float v) const { w.put(v); }
  void operator()(const char*, bool v) const { w.put(uint8_t(v)); }
  void operator()(const char*, const std::string& v) const { w.put_string(v); }
};

struct SettingReader {
  ByteReader& r;
  void operator()(const char*, int& v) const { v = r.get<int32_t>(); }
  void operator()(const char*, uint64_t& v) const { v = r.get<uint64_t>(); }
  void operator()(const char*, float& v) const { v = r.get<float>(); }
  void operator()(const char*, bool& v) const { v = r.get<uint8_t>() != 0; }
  void operator()(const char*, std::string& v) const { v = r.get_string(); }
};

void put_settings(ByteWriter& w, const RenderSettings& s) {
  for_each_sent_setting(s, SettingWriter{w});
}

RenderSettings get_settings(ByteReader& r) {
  RenderSettings s;
  for_each_sent_setting(s, SettingReader{r});
  if (s.spp < 0 || s.max_bounces < 0 || s.ao_rays < 0 || !std::isfinite(s.step_scale) ||
      !(s.step_scale > 0) || !std::isfinite(s.sample_clamp) || !(s.sample_clamp >= 0) ||
      s.catcher_axis < -1 || s.catcher_axis > 2 || !std::isfinite(s.catcher_height) ||
      !(s.catcher_albedo >= 0 && s.catcher_albedo <= 1))
    throw WireError("render settings out of range");
  return s;
}

ResultEncoding get_encoding(ByteReader& r) {
  const uint8_t e = r.get<uint8_t>();
  if (e >= kResultEncodings) throw WireError("unknown result encoding " + std::to_string(e));
  return ResultEncoding(e);
}

// A message that is one number.
template <class T>
std::vector<uint8_t> encode_scalar(T value) {
  ByteWriter w;
  w.put(value);
  return w.take();
}

}  // namespace

std::vector<uint8_t> encode(const HelloMessage& m) {
  ByteWriter w;
  w.put(uint8_t(m.ok)), w.put_string(m.error), w.put(uint64_t(m.devices.size()));
  for (const DeviceInfo& d : m.devices) put_info(w, d);
  w.put(uint64_t(m.fingerprint.size()));
  for (const FingerprintPart& p : m.fingerprint) w.put_string(p.what), w.put(p.hash);
  return w.take();
}

HelloMessage decode_hello(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  HelloMessage m;
  m.ok = r.get<uint8_t>() != 0, m.error = r.get_string();
  for (uint64_t n = r.count(8); n > 0; --n) m.devices.push_back(get_info(r));
  for (uint64_t n = r.count(16); n > 0; --n) {
    FingerprintPart p;
    p.what = r.get_string(), p.hash = r.get<uint64_t>();
    m.fingerprint.push_back(std::move(p));
  }
  return m;
}

std::vector<uint8_t> encode(const FrameMessage& m) {
  ByteWriter w;
  w.put(m.epoch);
  put_settings(w, m.settings);
  w.put(uint64_t(m.views.size()));
  for (size_t i = 0; i < m.views.size(); ++i) {
    const ViewSetup& v = m.views[i];
    w.put(v.camera.eye), w.put(v.camera.target), w.put(v.camera.up), w.put(v.camera.fov_y_deg);
    w.put(int32_t(v.camera.film_width)), w.put(int32_t(v.camera.film_height));
    w.put(int32_t(v.width)), w.put(int32_t(v.height)), w.put(v.view), w.put(v.frame);
    w.put(v.first_sample), w.put(v.sample_frame);
    w.put_array(i < m.spp_maps.size() ? m.spp_maps[i] : std::vector<uint8_t>{});
  }
  w.put(uint8_t(m.results));
  return w.take();
}

FrameMessage decode_frame(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  FrameMessage m;
  m.epoch = r.get<uint32_t>();
  m.settings = get_settings(r);
  for (uint64_t n = r.count(64); n > 0; --n) {
    ViewSetup v;
    v.camera.eye = r.get<Vec3>(), v.camera.target = r.get<Vec3>(), v.camera.up = r.get<Vec3>();
    v.camera.fov_y_deg = r.get<float>();
    v.camera.film_width = r.get<int32_t>(), v.camera.film_height = r.get<int32_t>();
    v.width = r.get<int32_t>(), v.height = r.get<int32_t>();
    v.view = r.get<uint32_t>(), v.frame = r.get<uint32_t>();
    v.first_sample = r.get<uint32_t>(), v.sample_frame = r.get<uint32_t>();
    if (v.width < 1 || v.height < 1 || v.width > kMaxSide || v.height > kMaxSide)
      throw WireError("view size out of range");
    m.spp_maps.push_back(r.get_array<uint8_t>());
    if (!m.spp_maps.back().empty() && m.spp_maps.back().size() != size_t(v.width) * v.height)
      throw WireError("sample map of the wrong size");
    m.views.push_back(v);
  }
  if (m.views.empty()) throw WireError("a frame without views");
  m.results = get_encoding(r);
  return m;
}

std::vector<uint8_t> encode(const WorkMessage& m) {
  ByteWriter w;
  w.put(m.epoch), w.put(uint8_t(m.batched)), w.put(uint8_t(m.report_ready));
  w.put(uint64_t(m.items.size()));
  for (size_t i = 0; i < m.items.size(); ++i) w.put(m.ids.at(i)), put_item(w, m.items[i]);
  return w.take();
}

WorkMessage decode_work(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  WorkMessage m;
  m.epoch = r.get<uint32_t>(), m.batched = r.get<uint8_t>() != 0;
  m.report_ready = r.get<uint8_t>() != 0;
  if (m.batched && m.report_ready) throw WireError("work: a batch reports no readiness");
  for (uint64_t n = r.count(24); n > 0; --n) {
    m.ids.push_back(r.get<uint32_t>());
    m.items.push_back(get_item(r));
  }
  return m;
}

std::vector<uint8_t> encode(const ResultMessage& m) {
  ByteWriter w;
  w.put(m.epoch), w.put(uint8_t(m.encoding)), w.put(uint64_t(m.items.size()));
  for (const ItemResult& it : m.items) {
    w.put(it.report.id), put_item(w, it.report.item);
    w.put(it.report.time_ms), w.put(it.report.busy_ms), w.put(it.report.samples), w.put(it.rays);
    put_pixels(w, it.pixels, m.encoding);
    w.put(uint8_t(it.features.empty() ? 0 : 1));
    if (!it.features.empty()) put_values(w, it.features.data(), it.features.size(), m.encoding);
  }
  w.put_array(m.local);
  w.put(m.idle_ms);
  return w.take();
}

ResultMessage decode_result(const std::vector<uint8_t>& bytes, const ResultBounds& bounds) {
  ByteReader r(bytes);
  ResultMessage m;
  m.epoch = r.get<uint32_t>();
  m.encoding = get_encoding(r);
  // Pixels this message may still hold: bounded before any item's pixels are read.
  int64_t budget = int64_t(bounds.width) * bounds.height * bounds.views;
  for (uint64_t n = r.count(60); n > 0; --n) {
    ItemResult it;
    it.report.id = r.get<uint32_t>(), it.report.item = get_item(r);
    it.report.time_ms = r.get<double>(), it.report.busy_ms = r.get<double>();
    it.report.samples = r.get<double>(), it.rays = r.get<uint64_t>();
    const WorkItem& item = it.report.item;
    if (item.rect.x1 > bounds.width || item.rect.y1 > bounds.height || item.view >= bounds.views)
      throw WireError("result outside the frame");
    budget -= item.rect.area();
    if (budget < 0) throw WireError("results of more pixels than the frame has");
    it.pixels = get_pixels(r, m.encoding, size_t(item.rect.area()));
    if (const uint8_t features = r.get<uint8_t>(); features > 1) {
      throw WireError("result: feature buffers flag out of range");
    } else if (features) {
      it.features.resize(size_t(item.rect.area()) * FeatureBuffers::kFloats);
      get_values(r, m.encoding, it.features.size(), it.features.data());
    }
    m.items.push_back(std::move(it));
  }
  m.local = r.get_array<LocalDeviceTime>();
  m.idle_ms = r.get<double>();
  if (!(m.idle_ms >= 0)) throw WireError("idle time out of range");
  return m;
}

std::vector<uint8_t> encode(const FailureMessage& m) {
  ByteWriter w;
  w.put(m.epoch), w.put_string(m.error);
  return w.take();
}

FailureMessage decode_failure(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  FailureMessage m;
  m.epoch = r.get<uint32_t>(), m.error = r.get_string();
  return m;
}

std::vector<uint8_t> encode_ready(uint32_t epoch) { return encode_scalar(epoch); }

uint32_t decode_ready(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  return r.get<uint32_t>();
}

std::vector<uint8_t> encode_speed(double speed) { return encode_scalar(speed); }

double decode_speed(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  const double s = r.get<double>();
  if (!(s >= kMinEmulatedSpeed && s <= 1.0)) throw WireError("emulated speed out of range");
  return s;
}

std::vector<uint8_t> encode_quit(bool rank_lost) {
  ByteWriter w;
  w.put(uint8_t(rank_lost));
  return w.take();
}

bool decode_quit(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  const uint8_t lost = r.get<uint8_t>();
  if (lost > 1) throw WireError("quit: rank_lost is neither 0 nor 1");
  return lost == 1;
}

}  // namespace multiray::remote
