// OSPRay's two MPI load balancers (OSPRay 1.x, modules/mpi: MPILoadBalancer.cpp and
// MPIOffloadDevice.cpp; the same tile ownership as its DistributedFrameBuffer), rewritten
// from their published sources so that multiray can be measured against them. The facts
// are OSPRay's; the code is ours. Both keep no statistics; Plan::ratios report the
// planned share of samples (`ospray-static`) or last frame's measured work shares
// (`ospray-dynamic`, like `queue`).
//
// `ospray-static` (staticLoadBalancer): the frame is cut into square tiles (OSPRay's
// TILE_SIZE, 64 px by default) numbered in scanline order, views one after another; tile
// t belongs to worker t mod N (tileID = taskIndex·N + rank), dropped devices left out of
// the count. Each worker renders its own tiles and nothing else: no queue, no stealing,
// and its results go to the master once per frame.
//
// `ospray-dynamic` (dynamicLoadBalancer, OSPRAY_DYNAMIC_LOADBALANCER=1): the master keeps
// the tiles and hands them out on request; each worker holds `prefetch` tiles in flight
// (OSPRay's preAllocatedTiles, OSPRAY_PREALLOCATED_TILES, default 4) to hide the round
// trip. At a frame's start the master sends each worker `prefetch` of the tiles it owns
// round-robin; the rest wait at the master. multiray's Plan expresses this as the
// pre-allocated tiles in Plan::assigned and the others in Plan::shared in scanline
// order, pulled `prefetch` at a time (Plan::batch); no stealing, since a tile once sent
// is the worker's. (OSPRay's master serves a worker from its own round-robin tiles first
// and then from the longest other list; one FIFO keeps the same granularity and differs
// only in which tile comes next, which matters to OSPRay's distributed frame buffer, not
// to multiray's devices.)
//
// | balancer       | parameter | default | meaning                                  |
// |----------------|-----------|---------|------------------------------------------|
// | ospray-static  | tile      | 64      | tile edge in pixels (1–4096)             |
// | ospray-dynamic | tile      | 64      | tile edge in pixels (1–4096)             |
// | ospray-dynamic | prefetch  | 4       | tiles per request and pre-allocated per  |
// |                |           |         | worker at the frame's start (1–1024)     |
#pragma once

#include "balance/balancer_base.h"

namespace multiray::balance {

class OsprayStaticBalancer final : public BalancerBase {
 public:
  explicit OsprayStaticBalancer(int device_count, int tile = 64);

  std::string name() const override { return "ospray-static"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override { drop_reported_dead(stats); }

 private:
  std::vector<bool> alive_mask() const;

  int tile_;
};

class OsprayDynamicBalancer final : public BalancerBase {
 public:
  OsprayDynamicBalancer(int device_count, int tile = 64, int prefetch = 4);

  std::string name() const override { return "ospray-dynamic"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

 private:
  std::vector<bool> alive_mask() const;

  int tile_, prefetch_;
  std::vector<double> measured_;  // last usable work shares
};

// The tiles of every view in scanline order, views one after another, each with its
// owner by OSPRay's round robin over the alive devices (tile t → t-th alive device mod
// alive count). `alive` has one entry per device. Exposed for tests.
struct OwnedTile {
  WorkItem item;
  int owner = 0;
};
std::vector<OwnedTile> round_robin_tiles(const FrameShape& shape, int tile,
                                         const std::vector<bool>& alive);

}  // namespace multiray::balance
