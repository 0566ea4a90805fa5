#include "core/machine_load.h"

#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace multiray {

namespace {

// The CPUs this process may run on.
std::vector<int> allowed_cpus() {
  std::vector<int> cpus;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

// Counts loop iterations on `cpu` (pinned) until `end`; 0 when it cannot be pinned.
uint64_t spin(int cpu, std::chrono::steady_clock::time_point end) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (pthread_setaffinity_np(pthread_self(), sizeof set, &set) != 0) return 0;
  uint64_t n = 0;
  volatile uint64_t sink = 0;
  while (std::chrono::steady_clock::now() < end)
    for (int k = 0; k < 1024; ++k) sink = sink + uint64_t(k), ++n;
  return n;
}

// Each of `cpus` spins for `ms` at the same time; the count of each.
std::vector<uint64_t> spin_all(const std::vector<int>& cpus, int ms) {
  std::vector<uint64_t> counts(cpus.size(), 0);
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  std::vector<std::thread> threads;
  for (size_t k = 0; k < cpus.size(); ++k)
    threads.emplace_back([&, k] { counts[k] = spin(cpus[k], end); });
  for (std::thread& t : threads) t.join();
  return counts;
}

}  // namespace

double contention_probe(int ms) {
  const std::vector<int> cpus = allowed_cpus();
  if (cpus.size() < 2 || ms <= 0) return 1.0;
  const uint64_t solo = spin_all({cpus.front()}, ms).front();
  const std::vector<uint64_t> all = spin_all(cpus, ms);
  double sum = 0;
  for (uint64_t c : all) {
    if (c == 0) return 1.0;  // not pinned: no comparison
    sum += double(c);
  }
  return solo > 0 ? sum / double(all.size()) / double(solo) : 1.0;
}

CpuTimes read_cpu_times() {
  CpuTimes t;
  std::ifstream in("/proc/stat");
  std::string cpu;
  uint64_t user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  if (!(in >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal) ||
      cpu != "cpu")
    return t;
  t.busy = user + nice + system + irq + softirq;
  t.idle = idle + iowait;
  t.steal = steal;
  t.valid = true;
  return t;
}

double steal_fraction(const CpuTimes& before, const CpuTimes& after) {
  if (!before.valid || !after.valid) return 0;
  const double steal = double(after.steal - before.steal);
  const double all = double(after.busy - before.busy) + double(after.idle - before.idle) + steal;
  return all > 0 ? steal / all : 0;
}

}  // namespace multiray
