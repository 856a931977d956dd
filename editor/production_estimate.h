#pragma once
// How long making one tile will take, learnt while tiles are made (§9.1: the paper had "no
// precise oracle to guess the generation time for a given quad", and its worst frames came from
// there). A tile's time grows with the vector data its quad holds: a coarse quad of thousands
// of fields costs ten to twenty times a leaf's. The estimate is a line, time = a + b x over
// x = the quad's curves and areas, fitted by least squares with exponentially decaying weights
// (recent tiles count most), one line per producer. The frame loop starts a tile only if its
// estimate fits in the budget left.
//
// Thread-safe: the production workers add samples and ask for estimates concurrently.

#include <cstddef>
#include <mutex>

namespace lacet {

class ProductionEstimate {
public:
    // Milliseconds to make a tile of a quad holding `elements` curves and areas (0 before the
    // first sample).
    double predict(std::size_t elements) const;
    // A tile of `elements` took `ms`.
    void add(std::size_t elements, double ms);
    // Whether a tile of `elements` is within what was measured (at most the largest sample's): a
    // prediction beyond it extrapolates the line, and a coarse quad of ten times more elements
    // than any seen yet may cost far more than it says.
    bool covers(std::size_t elements) const;
    // Whether a tile of `elements` may take longer than `ms`: beyond what was measured, or
    // predicted longer (the rule that leaves work to the background, editor/background_work.h).
    bool mayExceed(std::size_t elements, double ms) const { return !covers(elements) || predict(elements) > ms; }

private:
    static constexpr double kDecay = 0.995;  // weight of the previous samples at each new one
    mutable std::mutex mutex_;
    double w_ = 0.0, sx_ = 0.0, sy_ = 0.0, sxx_ = 0.0, sxy_ = 0.0;  // weighted sums
    bool any_ = false;
    std::size_t largest_ = 0;  // the most elements of a sample
};

}  // namespace lacet
