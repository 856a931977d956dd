#pragma once
// Frame-rate-adaptive quality (issue 16; Lerbour, Marvie & Gautron §9: "a generic quality factor
// ... adjusted until the target frame rate is obtained"): the K of the view (§8, the distance in
// quad sizes under which a quad is subdivided) is lowered while frames run over their budget and
// raised back towards the user's K when there is room, so the view stays interactive while DEM
// blocks stream in and tiles are made.
//
// Order of calls: construct with the user's K; after each frame, onFrame(its time, whether the
// view is complete) returns the K for the next frame (EditSession::setK). Decisions are taken on
// the median of the last `window` frames, at most once a window, so one slow frame changes nothing.
//
// Units: milliseconds; K is dimensionless.

#include <vector>

namespace lacet {

struct AdaptiveQualityParams {
    double targetMs = 16.7;  // the frame time aimed at (60 frames a second)
    double minK = 1.0;       // K is never lowered below this (the coarsest view allowed)
    double lower = 0.85;     // factor on K when the median frame is over the target
    double raise = 1.1;      // factor on K (up to the user's) when there is room
    double room = 0.6;       // there is room when the median frame is under this fraction of the target
    int window = 15;         // frames per decision
    void validate() const;   // std::invalid_argument naming the field out of its range
};

class AdaptiveQuality {
public:
    // userK > 0: the K the user chose, the ceiling.
    explicit AdaptiveQuality(double userK, AdaptiveQualityParams params = {});
    // Records a frame; returns the K to use next. K is raised only after frames that left nothing
    // pending (the view is complete: raising it would otherwise add work to a busy view).
    double onFrame(double frameMs, bool viewComplete);
    double K() const { return k_; }
    double userK() const { return userK_; }
    void setUserK(double k);  // the user changed K: it becomes the ceiling and the current value
    int lowered() const { return lowered_; }  // decisions taken each way so far
    int raised() const { return raised_; }

private:
    AdaptiveQualityParams p_;
    double userK_, k_;
    std::vector<double> times_;
    bool complete_ = true;
    int lowered_ = 0, raised_ = 0;
};

}  // namespace lacet
