// Messages between the ranks of one mpirun job, over MPI (Open MPI). One thread per
// process — the transport's — makes every MPI call (MPI_THREAD_SERIALIZED), with
// non-blocking sends, probes and receives only: a rank that died never answers and, with
// Open MPI 4.1, no MPI error ever reports it, so a blocking call to it would hang forever.
// That holds for a message already half received too: a link cut while a large message
// crosses it (tests/mpi/netfault.sh) leaves the rest of its bytes away for good, so a
// matched message is received with MPI_Imrecv and tested, never waited for. The other
// threads hand messages to send() and wait in receive() with a deadline.
//
// A message longer than kPartBytes crosses in parts, two at a time, each of which tells
// the receiver its sender is alive: the heartbeats wait behind the bytes in the same TCP
// stream, so a result that took longer than --worker-timeout to cross whole had its live
// sender given up on.
//
// Sending overlaps rendering: send() returns at once and the transport's thread moves
// the bytes while the caller renders the next item (Seo et al. 2022 use a sender thread
// per worker for the same overlap). On the master (rank 0), messages to and from workers
// cross the emulated link (link.h) when one is given.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "distributed/link.h"

namespace multiray::remote {

// The tag of the transport's own heartbeats (never delivered to receive()).
constexpr int kHeartbeatTag = 99;
// A message longer than kPartBytes crosses as parts: every part but the last with this
// tag, the last with the message's own; the receiver joins them and delivers one message.
// Each part that arrives counts as hearing from its sender. Sent whole, a result of
// several MB took longer than --worker-timeout across a slow link while the sender's
// heartbeats waited behind its bytes in the same TCP stream, and a live worker was given
// up on (2026-12-04: a 1.6 MB result at 2 Mbit/s, 6.5 s, against the test harness's 2 s).
constexpr int kPartTag = 98;
// 128 KiB: 0.5 s at 2 Mbit/s, a quarter of tests/mpi/netfault.sh's 2-s timeout (40 ms at
// 25 Mbit/s Wi-Fi). Above Open MPI's 64 KiB eager limit of its TCP transport, so a part
// can still be cut half received (what MPI_Imrecv is for, above); large enough that a
// 30 MB result is 230 parts, matched in one pass of the probe loop each.
constexpr size_t kPartBytes = size_t(128) << 10;
// Parts in flight to one peer at a time. Open MPI moves the bytes of every pending large
// send to a peer interleaved: twelve parts sent at once all completed together, at the
// end, as one whole message had. Two at a time keep one part crossing while the next is
// matched; a later message to that peer waits behind the parts (they would otherwise be
// joined to it), a heartbeat does not.
constexpr int kPartsInFlight = 2;

struct Message {
  int from = -1, tag = 0;
  std::vector<uint8_t> bytes;
};

// What crossed this rank's transport.
struct TransportStats {
  uint64_t messages_sent = 0, bytes_sent = 0, messages_received = 0, bytes_received = 0;
};

class Transport {
 public:
  using Clock = std::chrono::steady_clock;

  // Initialises MPI (once per process; MPI_THREAD_SERIALIZED or better) and starts the
  // transport's thread. Throws DeviceError when MPI cannot start or lacks thread support.
  // `link` is emulated on rank 0 only.
  explicit Transport(LinkSpec link = {});
  // Stops the thread and finalises MPI, unless a rank was given up on here or elsewhere
  // (forgo_finalize): MPI_Finalize waits for every rank of the job, a dead one forever.
  // MPI is then left as is and the process ends without it (mpiexec --enable-recovery
  // lets it).
  ~Transport();
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  const LinkSpec& link() const { return link_.spec(); }

  // Queues `bytes` for rank `to`; returns at once. Throws DeviceError for a message of
  // 2 GiB or more (an MPI count is an int).
  void send(int to, int tag, std::vector<uint8_t> bytes);
  // The same bytes to several ranks without a copy each (a scene to every worker).
  void send(int to, int tag, std::shared_ptr<const std::vector<uint8_t>> bytes);
  // The oldest message from `from` (-1: anyone), waiting until `deadline`; nullopt when
  // none arrived in time (or the transport is stopping).
  std::optional<Message> receive(int from, Clock::time_point deadline);
  // When anything (a heartbeat included) last arrived from `peer`.
  Clock::time_point last_heard(int peer) const;
  // Marks `peer` as given up on: its messages are dropped from now on.
  void give_up(int peer);
  bool gave_up_on_anyone() const;
  // Another rank gave up on one (a worker told so by the master): this rank must not
  // finalise MPI either, although every peer it talks to still answers.
  void forgo_finalize() { forgo_finalize_ = true; }
  // Sends a heartbeat every `period`: a worker to rank 0, so the master tells a busy
  // worker from a dead one; the master to every worker, so a worker notices a dead master.
  // Zero: none.
  void set_heartbeat(std::chrono::milliseconds period) { heartbeat_ms_ = period.count(); }
  TransportStats stats() const;

 private:
  struct Outgoing {
    Clock::time_point release;
    int to, tag;
    std::shared_ptr<const std::vector<uint8_t>> bytes;
  };
  struct Delayed {
    Clock::time_point deliver;
    Message message;
  };
  struct InFlight;
  struct Arriving;
  // A message leaving in parts: the next part starts at `at`.
  struct Sending {
    int tag;
    std::shared_ptr<const std::vector<uint8_t>> bytes;
    size_t at;
  };
  void loop();
  // One pass of the transport's thread; true when it moved anything.
  bool pump();
  // Starts sends of the next parts to `to` while fewer than kPartsInFlight are under way;
  // true when it started any.
  bool send_parts(int to);
  bool probe_one();
  // Moves completed receives to delivery, each peer's in the order they matched; true
  // when it moved anything.
  bool finish_receives();
  void send_heartbeats();

  int rank_ = 0, size_ = 1;
  LinkModel link_;
  std::atomic<int64_t> heartbeat_ms_{0};
  mutable std::mutex mutex_;
  std::condition_variable arrived_;  // a message reached the inbox
  std::condition_variable wake_;     // a message was queued to send
  std::deque<Outgoing> outbox_;
  std::vector<Delayed> delayed_;  // received, not yet delivered by the emulated link
  std::deque<Message> inbox_;
  std::vector<Clock::time_point> heard_;
  std::vector<bool> given_up_;
  std::vector<std::unique_ptr<InFlight>> in_flight_;  // transport thread only
  // Messages matched and being received, in the order they matched (transport thread
  // only). A receive from a peer given up on may never complete (its link is down): it is
  // left here, its buffer kept, since MPI may still write into it.
  std::deque<std::unique_ptr<Arriving>> arriving_;
  // Per peer, the parts (kPartTag) of a message whose last part has not come yet
  // (transport thread only).
  std::vector<std::vector<uint8_t>> parts_;
  // Per peer, the messages leaving in parts, oldest first, and how many of their parts'
  // sends are under way (transport thread only).
  std::vector<std::deque<Sending>> sending_;
  std::vector<int> parts_in_flight_;
  TransportStats stats_;
  bool stop_ = false;
  std::atomic<bool> forgo_finalize_{false};
  std::thread thread_;
};

}  // namespace multiray::remote
