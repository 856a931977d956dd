#pragma once
// Small helpers of the benchmark tasks: clocks, medians, peak memory.

#include <chrono>
#include <cstddef>
#include <vector>

#include "model/work_clock.h"

namespace lacet::bench {

using Clock = std::chrono::steady_clock;
using lacet::msSince;  // model/work_clock.h
// Quantile q in [0, 1] (nearest rank) of a copy of v; 0 for an empty v.
double quantile(std::vector<double> v, double q);
inline double median(const std::vector<double>& v) { return quantile(v, 0.5); }
// Peak resident set size of this process so far, MiB.
double peakRssMiB();

}  // namespace lacet::bench
