// What else the machine is doing, measured around a benchmark: a contention probe (busy
// loops on one core, then on every core at once) and the CPU time counters of
// /proc/stat (Linux), whose "steal" is time the hypervisor gave our virtual CPUs to
// someone else.
#pragma once

#include <cstdint>

namespace multiray {

// Spins a counting loop for `ms` on the first CPU this process may run on, then on every
// such CPU at once (one thread each, pinned), and returns the mean per-CPU count of the
// second run / the count of the first: 1.0 when nothing else runs, 0.5 when all our CPUs
// together got half of their time. 1.0 with a single CPU (nothing to compare) or when
// threads cannot be pinned. Takes 2 × ms.
double contention_probe(int ms);

// Jiffies summed over all CPUs (/proc/stat's first line); all zero where unreadable.
struct CpuTimes {
  uint64_t busy = 0;   // user + nice + system + irq + softirq
  uint64_t idle = 0;   // idle + iowait
  uint64_t steal = 0;  // taken by the hypervisor
  bool valid = false;
};
CpuTimes read_cpu_times();

// The steal share of all CPU time between two readings (0 when either is invalid or no
// time passed).
double steal_fraction(const CpuTimes& before, const CpuTimes& after);

}  // namespace multiray
