#include "distributed/transport.h"

#include <mpi.h>

#include <algorithm>
#include <limits>

#include "core/error.h"

namespace multiray::remote {

struct Transport::InFlight {
  MPI_Request request = MPI_REQUEST_NULL;
  int to = 0;
  bool part = false;                                  // of a message (not a heartbeat)
  std::shared_ptr<const std::vector<uint8_t>> bytes;  // kept until the send completes
};

struct Transport::Arriving {
  MPI_Request request = MPI_REQUEST_NULL;
  Message message;  // its bytes are the receive buffer
  bool done = false;
};

namespace {
// How long the transport's thread sleeps when nothing moved (MPI has no wake-up for an
// arriving message, so arrivals are polled): 20 us after any traffic, doubling while
// nothing moves up to 200 us, so that 17 ranks on two cores do not spend them polling.
// A message to send wakes the thread at once.
constexpr auto kMinSleep = std::chrono::microseconds(20);
constexpr auto kMaxSleep = std::chrono::microseconds(200);
// How long the destructor lets queued messages (Quit to every worker) drain.
constexpr auto kDrainLimit = std::chrono::seconds(3);
}  // namespace

Transport::Transport(LinkSpec link) : link_(std::move(link), 1) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
      throw DeviceError("MPI could not be initialised");
    if (provided < MPI_THREAD_SERIALIZED)
      throw DeviceError("this MPI library has no MPI_THREAD_SERIALIZED support");
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  link_ = LinkModel(rank_ == 0 ? link_.spec() : LinkSpec{}, std::max(1, size_ - 1));
  heard_.assign(size_t(size_), Clock::now());
  given_up_.assign(size_t(size_), false);
  parts_.assign(size_t(size_), {});
  sending_.assign(size_t(size_), {});
  parts_in_flight_.assign(size_t(size_), 0);
  thread_ = std::thread([this] { loop(); });
}

Transport::~Transport() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  arrived_.notify_all();
  thread_.join();
  // A receive that never completed (from a peer whose link went down mid-message) keeps
  // its buffer: MPI may still write into it should the bytes come after all.
  for (auto& a : arriving_)
    if (!a->done) static_cast<void>(a.release());
  if (!gave_up_on_anyone() && !forgo_finalize_) MPI_Finalize();
}

void Transport::send(int to, int tag, std::vector<uint8_t> bytes) {
  send(to, tag, std::make_shared<const std::vector<uint8_t>>(std::move(bytes)));
}

void Transport::send(int to, int tag, std::shared_ptr<const std::vector<uint8_t>> bytes) {
  if (bytes->size() > size_t(std::numeric_limits<int>::max()))
    throw DeviceError("a message of " + std::to_string(bytes->size() >> 20) +
                      " MiB is more than MPI sends at once (2 GiB)");
  std::lock_guard<std::mutex> lock(mutex_);
  const Clock::time_point now = Clock::now();
  const Clock::time_point release =
      rank_ == 0 && to > 0 ? link_.deliver_at(to - 1, bytes->size(), now) : now;
  outbox_.push_back(Outgoing{release, to, tag, std::move(bytes)});
  wake_.notify_one();
}

std::optional<Message> Transport::receive(int from, Clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    const auto it = std::find_if(inbox_.begin(), inbox_.end(),
                                 [&](const Message& m) { return from < 0 || m.from == from; });
    if (it != inbox_.end()) {
      Message m = std::move(*it);
      inbox_.erase(it);
      return m;
    }
    if (stop_ || arrived_.wait_until(lock, deadline) == std::cv_status::timeout) {
      if (Clock::now() >= deadline || stop_) return std::nullopt;
    }
  }
}

Transport::Clock::time_point Transport::last_heard(int peer) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return heard_.at(size_t(peer));
}

void Transport::give_up(int peer) {
  std::lock_guard<std::mutex> lock(mutex_);
  given_up_.at(size_t(peer)) = true;
  inbox_.erase(std::remove_if(inbox_.begin(), inbox_.end(),
                              [&](const Message& m) { return m.from == peer; }),
               inbox_.end());
}

bool Transport::gave_up_on_anyone() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::find(given_up_.begin(), given_up_.end(), true) != given_up_.end();
}

TransportStats Transport::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void Transport::loop() {
  Clock::time_point beat = Clock::now();
  Clock::time_point drain_until{};
  auto sleep = kMinSleep;
  for (;;) {
    const bool moved = pump();
    sleep = moved ? kMinSleep : std::min(kMaxSleep, sleep * 2);
    const Clock::time_point now = Clock::now();
    const auto period = std::chrono::milliseconds(heartbeat_ms_.load());
    if (period.count() > 0 && now - beat >= period) {
      beat = now;
      send_heartbeats();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    if (stop_) {
      if (drain_until == Clock::time_point{}) drain_until = now + kDrainLimit;
      bool pending = !outbox_.empty();
      for (const auto& f : in_flight_) pending |= !given_up_[size_t(f->to)];
      for (int r = 0; r < size_; ++r)
        pending |= !sending_[size_t(r)].empty() && !given_up_[size_t(r)];
      if (!pending || now >= drain_until) break;
    }
    // Sleeps unless a message became due to send (a wake-up from send(), or a release
    // time of the emulated link within the sleep).
    auto until = now + sleep;
    for (const Outgoing& o : outbox_) until = std::min(until, o.release);
    if (!moved && until > now) wake_.wait_until(lock, until);
  }
  for (auto& f : in_flight_)
    if (f->request != MPI_REQUEST_NULL && !given_up_[size_t(f->to)]) MPI_Request_free(&f->request);
}

void Transport::send_heartbeats() {
  // A worker beats to the master; the master to every worker it has not given up on.
  std::vector<int> peers;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (int r = rank_ == 0 ? 1 : 0; r < (rank_ == 0 ? size_ : 1); ++r)
      if (!given_up_[size_t(r)]) peers.push_back(r);
  }
  for (const int r : peers) {
    auto f = std::make_unique<InFlight>();
    f->to = r;
    MPI_Isend(nullptr, 0, MPI_BYTE, r, kHeartbeatTag, MPI_COMM_WORLD, &f->request);
    in_flight_.push_back(std::move(f));
  }
}

bool Transport::pump() {
  bool moved = false;
  const Clock::time_point now = Clock::now();
  // Due messages leave, in order (the emulated link releases them monotonically per peer).
  std::vector<Outgoing> due;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = outbox_.begin(); it != outbox_.end();)
      if (it->release <= now) {
        due.push_back(std::move(*it));
        it = outbox_.erase(it);
      } else {
        ++it;
      }
  }
  // Each leaves in parts behind that peer's earlier messages (send_parts).
  for (Outgoing& o : due) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stats_.messages_sent++, stats_.bytes_sent += o.bytes->size();
    }
    sending_[size_t(o.to)].push_back(Sending{o.tag, std::move(o.bytes), 0});
    moved = true;
  }
  // Finished sends release their buffers and make room for the next parts.
  for (auto it = in_flight_.begin(); it != in_flight_.end();) {
    int done = 0;
    MPI_Test(&(*it)->request, &done, MPI_STATUS_IGNORE);
    if (done && (*it)->part) --parts_in_flight_[size_t((*it)->to)], moved = true;
    it = done ? in_flight_.erase(it) : it + 1;
  }
  for (int to = 0; to < size_; ++to)
    if (send_parts(to)) moved = true;
  while (probe_one()) moved = true;
  if (finish_receives()) moved = true;
  // The emulated link delivers what is due.
  std::lock_guard<std::mutex> lock(mutex_);
  bool delivered = false;
  std::stable_sort(delayed_.begin(), delayed_.end(),
                   [](const Delayed& a, const Delayed& b) { return a.deliver < b.deliver; });
  while (!delayed_.empty() && delayed_.front().deliver <= now) {
    inbox_.push_back(std::move(delayed_.front().message));
    delayed_.erase(delayed_.begin());
    delivered = true;
  }
  if (delivered) arrived_.notify_all();
  return moved || delivered;
}

bool Transport::send_parts(int to) {
  std::deque<Sending>& queue = sending_[size_t(to)];
  bool sent = false;
  while (parts_in_flight_[size_t(to)] < kPartsInFlight && !queue.empty()) {
    Sending& m = queue.front();
    const size_t size = m.bytes->size(), n = std::min(kPartBytes, size - m.at);
    const bool last = m.at + n == size;
    auto f = std::make_unique<InFlight>();
    f->to = to, f->part = true, f->bytes = m.bytes;
    MPI_Isend(f->bytes->data() + m.at, int(n), MPI_BYTE, to, last ? m.tag : kPartTag,
              MPI_COMM_WORLD, &f->request);
    in_flight_.push_back(std::move(f));
    ++parts_in_flight_[size_t(to)];
    m.at += n;
    if (last) queue.pop_front();
    sent = true;
  }
  return sent;
}

bool Transport::probe_one() {
  int flag = 0;
  MPI_Message handle = MPI_MESSAGE_NULL;
  MPI_Status status;
  MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &handle, &status);
  if (!flag) return false;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  auto a = std::make_unique<Arriving>();
  a->message.from = status.MPI_SOURCE;
  a->message.tag = status.MPI_TAG;
  a->message.bytes.resize(size_t(std::max(count, 0)));
  // Matched, not waited for: the rest of a large message (beyond the first fragment that
  // made it match) may never come when the sender's link went down as it crossed, and a
  // blocking MPI_Recv here stalled every peer's messages and heartbeats with it.
  MPI_Imrecv(a->message.bytes.data(), count, MPI_BYTE, &handle, &a->request);
  {
    // Its first bytes arrived: the peer was alive then.
    std::lock_guard<std::mutex> lock(mutex_);
    const int from = a->message.from;
    if (from >= 0 && from < size_ && !given_up_[size_t(from)]) heard_[size_t(from)] = Clock::now();
  }
  arriving_.push_back(std::move(a));
  return true;
}

bool Transport::finish_receives() {
  for (auto& a : arriving_)
    if (!a->done) {
      int done = 0;
      MPI_Test(&a->request, &done, MPI_STATUS_IGNORE);
      a->done = done != 0;
    }
  bool moved = false;
  std::vector<bool> waiting(size_t(size_), false);  // an earlier message of this peer is not in
  const Clock::time_point now = Clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = arriving_.begin(); it != arriving_.end();) {
    const int from = (*it)->message.from;
    const bool known = from >= 0 && from < size_;
    if (!(*it)->done || (known && waiting[size_t(from)])) {
      if (known) waiting[size_t(from)] = true;  // each peer's messages in the order they matched
      ++it;
      continue;
    }
    Message m = std::move((*it)->message);
    it = arriving_.erase(it);
    moved = true;
    if (!known) continue;
    std::vector<uint8_t>& parts = parts_[size_t(from)];
    if (given_up_[size_t(from)]) {
      std::vector<uint8_t>().swap(parts);  // its message will never be whole
      continue;
    }
    heard_[size_t(from)] = now;
    if (m.tag == kHeartbeatTag) continue;
    if (m.tag == kPartTag) {  // parts of a peer's message come in order (MPI's rule)
      parts.insert(parts.end(), m.bytes.begin(), m.bytes.end());
      continue;
    }
    if (!parts.empty()) {
      parts.insert(parts.end(), m.bytes.begin(), m.bytes.end());
      m.bytes = std::move(parts);
      parts = {};
    }
    stats_.messages_received++, stats_.bytes_received += m.bytes.size();
    const Clock::time_point at =
        rank_ == 0 && m.from > 0 ? link_.deliver_at(m.from - 1, m.bytes.size(), now) : now;
    delayed_.push_back(Delayed{at, std::move(m)});
  }
  return moved;
}

}  // namespace multiray::remote
