#include "editor/adaptive_quality.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lacet {

void AdaptiveQualityParams::validate() const {
    auto need = [](bool ok, const char* what) {
        if (!ok) throw std::invalid_argument(std::string("AdaptiveQualityParams: ") + what);
    };
    need(std::isfinite(targetMs) && targetMs > 0.0, "targetMs must be > 0");
    need(std::isfinite(minK) && minK > 0.0, "minK must be > 0");
    need(lower > 0.0 && lower < 1.0, "lower must be in (0, 1)");
    need(std::isfinite(raise) && raise > 1.0, "raise must be > 1");
    need(room > 0.0 && room < 1.0, "room must be in (0, 1)");
    need(window >= 1, "window must be >= 1");
}

AdaptiveQuality::AdaptiveQuality(double userK, AdaptiveQualityParams params) : p_(params), userK_(userK), k_(userK) {
    p_.validate();
    setUserK(userK);
}

void AdaptiveQuality::setUserK(double k) {
    if (!std::isfinite(k) || k <= 0.0) throw std::invalid_argument("AdaptiveQuality: K must be > 0, got " + std::to_string(k));
    userK_ = k;
    k_ = k;
    times_.clear();
    complete_ = true;
}

double AdaptiveQuality::onFrame(double frameMs, bool viewComplete) {
    times_.push_back(frameMs);
    complete_ = complete_ && viewComplete;
    if (int(times_.size()) < p_.window) return k_;
    std::nth_element(times_.begin(), times_.begin() + std::ptrdiff_t(times_.size() / 2), times_.end());
    const double median = times_[times_.size() / 2];
    const double floorK = std::min(p_.minK, userK_);
    if (median > p_.targetMs && k_ > floorK) {
        k_ = std::max(floorK, k_ * p_.lower);
        ++lowered_;
    } else if (median < p_.room * p_.targetMs && complete_ && k_ < userK_) {
        k_ = std::min(userK_, k_ * p_.raise);
        ++raised_;
    }
    times_.clear();
    complete_ = true;
    return k_;
}

}  // namespace lacet
