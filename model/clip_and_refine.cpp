#include "model/clip_and_refine.h"

#include <algorithm>
#include <bit>
#include <cstdint>

#include "model/bezier.h"
#include "model/graph.h"
#include "model/sector_walk.h"

namespace lacet {
namespace {

// One piece of the parent after refinement: kept in the quad, or dropped (wholly outside).
struct Event {
    BezierPiece b;
    bool kept = false;
    double t0 = 0.0, t1 = 1.0;  // parameter range of b within the parent piece (dyadic, exact)
};

bool lexLess(Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// True when the reversed piece comes first in lexicographic order of its points. Refining every
// piece in that canonical direction makes the two areas sharing a border curve refine it into
// the same sub-pieces, bit for bit, whatever direction their loops walk it.
bool canonicalIsReversed(const BezierPiece& b) {
    for (int i = 0; i <= b.degree; ++i) {
        const Vec2 a = b.p[i], r = b.p[b.degree - i];
        if (a != r) return lexLess(r, a);
    }
    return false;
}

class Refiner {
public:
    Refiner(const Box& quad, double margin, double tolerance)
        : box_(quad.dilated(margin)), tolerance_(tolerance), quadSize_(quad.size().x) {}

    const Box& box() const { return box_; }

    void refine(const BezierPiece& b, std::vector<Event>& out) const { run(b, 0, 0.0, 1.0, out); }

    void refineCanonical(const BezierPiece& b, std::vector<Event>& out) const {
        if (!canonicalIsReversed(b)) return refine(b, out);
        const std::size_t first = out.size();
        refine(b.reversed(), out);
        std::reverse(out.begin() + std::ptrdiff_t(first), out.end());
        for (std::size_t i = first; i < out.size(); ++i) out[i].b = out[i].b.reversed();
    }

private:
    void run(const BezierPiece& b, int depth, double t0, double t1, std::vector<Event>& out) const {
        const Box cb = controlBounds(b);
        if (!cb.intersects(box_) || !tightBounds(b).intersects(box_)) {
            out.push_back({b, false, t0, t1});
            return;
        }
        // A piece larger than the quad is split even when flat, so that its parts far from the
        // quad are dropped (tighter conservative clipping). The decision depends only on the piece
        // and the level, not on the quad: adjacent quads refine a piece they share identically.
        const bool large = std::max(cb.size().x, cb.size().y) > quadSize_;
        if (depth >= kMaxRefineDepth || (!large && flatness(b) <= tolerance_)) {
            out.push_back({b, true, t0, t1});
            return;
        }
        const auto [l, r] = splitHalf(b);
        const double tm = (t0 + t1) * 0.5;
        run(l, depth + 1, t0, tm, out);
        run(r, depth + 1, tm, t1, out);
    }

    Box box_;
    double tolerance_;
    double quadSize_;
};

void appendPiece(const BezierPiece& b, std::vector<Vertex>& v) {
    if (v.empty()) v.push_back({b.p[0], true, false});
    for (int i = 1; i < b.degree; ++i) v.push_back({b.p[i], false, false});
    v.push_back({b.p[b.degree], true, false});
}

ClippedLoop boxLoop(const SectorWalk& walk, bool counterClockwise, bool hole) {
    ClippedLoop loop;
    loop.hole = hole;
    for (int k = 0; k <= 4; ++k) loop.vertices.push_back({walk.corner(counterClockwise ? k : -k), true, true});
    loop.vertices.back().closing = false;
    return loop;
}

// The steps a run of dropped events turns around the box.
int turnOf(const SectorWalk& walk, const std::vector<Event>& ev, std::size_t from, std::size_t to) {
    int steps = 0;
    for (std::size_t i = from; i < to; ++i) steps += walk.steps(ev[i % ev.size()].b.start(), ev[i % ev.size()].b.end());
    return steps;
}

// Clips one closed loop. Returns false when it has no kept piece; `turn` is then its whole turn
// around the box, in steps (4 per turn).
bool clipLoop(const ClippedLoop& in, const Refiner& refiner, const SectorWalk& walk, std::vector<Event>& ev,
              ClippedLoop& out, int& turn) {
    ev.clear();
    forEachPiece(in.vertices, [&](const BezierPiece& b, std::size_t first) {
        // Closing pieces lie on or outside the parent's dilated border, hence outside this one's
        // and in a half-plane that excludes the quad: they are always replaced.
        if (in.vertices[first].closing) ev.push_back({b, false});
        else refiner.refineCanonical(b, ev);
    });
    const auto firstKept = std::find_if(ev.begin(), ev.end(), [](const Event& e) { return e.kept; });
    if (firstKept == ev.end()) {
        turn = turnOf(walk, ev, 0, ev.size());
        return false;
    }
    out.hole = in.hole;
    out.vertices.clear();
    const std::size_t k0 = std::size_t(firstKept - ev.begin());
    const std::size_t n = ev.size();
    std::vector<Vec2> corners;
    for (std::size_t i = 0; i < n;) {
        const Event& e = ev[(k0 + i) % n];
        if (e.kept) {
            appendPiece(e.b, out.vertices);
            ++i;
            continue;
        }
        const std::size_t runStart = i;
        while (i < n && !ev[(k0 + i) % n].kept) ++i;
        const int steps = turnOf(walk, ev, k0 + runStart, k0 + i);
        corners.clear();
        walk.appendCorners(walk.sector(e.b.start()), steps, corners);
        out.vertices.back().closing = true;
        for (Vec2 c : corners) out.vertices.push_back({c, true, true});
        const Vec2 q = i < n ? ev[(k0 + i) % n].b.start() : out.vertices.front().p;
        out.vertices.push_back({q, true, false});
    }
    return true;
}

}  // namespace

void clipAndRefineCurve(const ClippedCurve& parent, std::uint32_t parentIndex, const Box& quad, double margin,
                        double tolerance, std::vector<ClippedCurve>& out) {
    const Refiner refiner(quad, margin, tolerance);
    thread_local std::vector<Event> ev;
    thread_local std::vector<std::pair<double, double>> range;  // ancestor parameters of each event
    ev.clear();
    range.clear();
    std::size_t piece = 0;
    forEachPiece(parent.vertices, [&](const BezierPiece& b, std::size_t) {
        const std::size_t first = ev.size();
        refiner.refine(b, ev);
        const double sa = parent.s[piece], sb = parent.s[piece + 1];
        for (std::size_t i = first; i < ev.size(); ++i)
            range.emplace_back(sa + (sb - sa) * ev[i].t0, sa + (sb - sa) * ev[i].t1);
        ++piece;
    });
    std::size_t current = SIZE_MAX;
    for (std::size_t i = 0; i < ev.size(); ++i) {
        if (!ev[i].kept) {
            current = SIZE_MAX;
            continue;
        }
        if (current == SIZE_MAX) {
            current = out.size();
            ClippedCurve run;
            run.parentIndex = parentIndex;
            run.startsAtNode = parent.startsAtNode && i == 0;
            run.s.push_back(range[i].first);
            out.push_back(std::move(run));
        }
        appendPiece(ev[i].b, out[current].vertices);
        out[current].s.push_back(range[i].second);
    }
    if (current != SIZE_MAX) out[current].endsAtNode = parent.endsAtNode;
}

void clipAndRefineArea(const ClippedArea& parent, std::uint32_t parentIndex, const Box& quad, double margin,
                       double tolerance, std::vector<ClippedArea>& out) {
    const Refiner refiner(quad, margin, tolerance);
    const SectorWalk walk(refiner.box());
    thread_local std::vector<Event> ev;
    ClippedArea result;
    result.parentIndex = parentIndex;
    bool anyKept = false, outerSurrounds = false, holeSurrounds = false;
    for (const ClippedLoop& in : parent.loops) {
        ClippedLoop loop;
        int turn = 0;
        if (clipLoop(in, refiner, walk, ev, loop, turn)) {
            anyKept = true;
            result.loops.push_back(std::move(loop));
        } else if (turn != 0) {
            (in.hole ? holeSurrounds : outerSurrounds) = true;
            result.loops.push_back(boxLoop(walk, turn > 0, in.hole));
        }
    }
    if (!anyKept) {
        // No border near the quad: it is inside the area, or outside it (or inside a hole).
        if (!outerSurrounds || holeSurrounds) return;
        result.loops.assign(1, boxLoop(walk, true, false));
        result.coversQuad = true;
    }
    if (!result.loops.empty()) out.push_back(std::move(result));
}

}  // namespace lacet

namespace lacet {

bool identical(const std::vector<Vertex>& a, const std::vector<Vertex>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].onCurve != b[i].onCurve || a[i].closing != b[i].closing) return false;
        if (std::bit_cast<std::uint64_t>(a[i].p.x) != std::bit_cast<std::uint64_t>(b[i].p.x) ||
            std::bit_cast<std::uint64_t>(a[i].p.y) != std::bit_cast<std::uint64_t>(b[i].p.y))
            return false;
    }
    return true;
}

bool identical(const ClippedCurve& a, const ClippedCurve& b) {
    if (a.s.size() != b.s.size()) return false;
    for (std::size_t i = 0; i < a.s.size(); ++i)
        if (std::bit_cast<std::uint64_t>(a.s[i]) != std::bit_cast<std::uint64_t>(b.s[i])) return false;
    return a.parentIndex == b.parentIndex && a.startsAtNode == b.startsAtNode && a.endsAtNode == b.endsAtNode &&
           identical(a.vertices, b.vertices);
}

bool identical(const ClippedArea& a, const ClippedArea& b) {
    if (a.parentIndex != b.parentIndex || a.coversQuad != b.coversQuad || a.loops.size() != b.loops.size()) return false;
    for (std::size_t i = 0; i < a.loops.size(); ++i)
        if (a.loops[i].hole != b.loops[i].hole || !identical(a.loops[i].vertices, b.loops[i].vertices)) return false;
    return true;
}

}  // namespace lacet
