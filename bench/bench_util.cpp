#include "bench/bench_util.h"

#include <algorithm>
#include <cmath>

#include <sys/resource.h>

namespace lacet::bench {

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const auto i = std::size_t(std::clamp(std::ceil(q * double(v.size())) - 1.0, 0.0, double(v.size() - 1)));
    return v[i];
}

double peakRssMiB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace lacet::bench
