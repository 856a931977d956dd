#include "editor/production_estimate.h"

#include <algorithm>

namespace lacet {

double ProductionEstimate::predict(std::size_t elements) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (w_ <= 0.0) return 0.0;
    const double x = double(elements);
    const double meanX = sx_ / w_, meanY = sy_ / w_;
    const double varX = sxx_ / w_ - meanX * meanX;
    // Too little spread in x for a slope (every tile alike so far): the mean.
    const double slope = varX > 1e-9 * std::max(1.0, meanX * meanX) ? std::max(0.0, (sxy_ / w_ - meanX * meanY) / varX) : 0.0;
    return std::max(0.0, meanY + slope * (x - meanX));
}

void ProductionEstimate::add(std::size_t elements, double ms) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const double x = double(elements);
    w_ = kDecay * w_ + 1.0;
    sx_ = kDecay * sx_ + x;
    sy_ = kDecay * sy_ + ms;
    sxx_ = kDecay * sxx_ + x * x;
    sxy_ = kDecay * sxy_ + x * ms;
    any_ = true;
    largest_ = std::max(largest_, elements);
}

bool ProductionEstimate::covers(std::size_t elements) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return any_ && elements <= largest_;
}

}  // namespace lacet
