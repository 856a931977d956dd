#include "io/network_builder.h"

#include <algorithm>
#include <cmath>
#include <bit>
#include <memory>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace lacet {
namespace {

struct PointKey {
    std::uint64_t x, y;
    explicit PointKey(Vec2 p) : x(std::bit_cast<std::uint64_t>(p.x)), y(std::bit_cast<std::uint64_t>(p.y)) {}
    friend bool operator==(const PointKey&, const PointKey&) = default;
};
struct PointHash {
    std::size_t operator()(const PointKey& k) const { return std::hash<std::uint64_t>()(k.x * 0x9e3779b97f4a7c15ULL ^ k.y); }
};

// A segment between two points, in either direction.
struct SegmentKey {
    PointKey a, b;
    SegmentKey(Vec2 p, Vec2 q) : a(p), b(q) {
        if (std::tie(b.x, b.y) < std::tie(a.x, a.y)) std::swap(a, b);
    }
    friend bool operator==(const SegmentKey&, const SegmentKey&) = default;
};
struct SegmentHash {
    std::size_t operator()(const SegmentKey& k) const { return PointHash()(k.a) * 0x100000001b3ULL ^ PointHash()(k.b); }
};

// The rings of an area, independent of where each ring starts and of its direction.
std::vector<std::uint64_t> ringsKey(const std::vector<std::vector<Vec2>>& rings) {
    std::vector<std::uint64_t> key;
    for (const std::vector<Vec2>& ring : rings) {
        std::vector<std::pair<std::uint64_t, std::uint64_t>> pts;
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            const PointKey k(ring[i]);
            pts.push_back({k.x, k.y});
        }
        const auto first = std::min_element(pts.begin(), pts.end());
        std::rotate(pts.begin(), first, pts.end());
        if (pts.size() > 2 && pts.back() < pts[1]) std::reverse(pts.begin() + 1, pts.end());
        key.push_back(pts.size());
        for (const auto& [x, y] : pts) key.insert(key.end(), {x, y});
    }
    return key;
}
struct KeyHash {
    std::size_t operator()(const std::vector<std::uint64_t>& k) const {
        std::size_t h = 0xcbf29ce484222325ULL;
        for (std::uint64_t v : k) h = (h ^ v) * 0x100000001b3ULL;
        return h;
    }
};

// A piece of a way between two nodes, in scene metres.
struct Piece {
    std::vector<Vec2> points;
    std::size_t rule;
    std::uint16_t flags;
    std::size_t a, b;  // end node indices
    const std::map<std::string, std::string>* kept = nullptr;
    bool alive = true;
};

std::vector<Vec2> project(const SceneFrame& frame, const std::vector<glm::dvec2>& lonLat) {
    std::vector<Vec2> out;
    out.reserve(lonLat.size());
    for (const glm::dvec2& p : lonLat) {
        const Vec2 q = frame.forward(p);
        if (out.empty() || out.back() != q) out.push_back(q);
    }
    return out;
}

class LayerBuilder {
public:
    LayerBuilder(Layer& layer, LayerId id, LayerSummary& summary, const FeatureMapping& mapping, const SplineFitParams& fit,
                 NetworkReport& report, std::vector<ElementAttribute>* attributes)
        : layer_(layer), id_(id), summary_(summary), mapping_(mapping), fit_(fit), report_(report), attributes_(attributes) {}

    // Adds the stretches of the way made of segments not imported before in this layer.
    void addWay(const std::vector<Vec2>& points, std::size_t rule, std::uint16_t flags, const std::map<std::string, std::string>& kept,
                const SourceRef& source) {
        std::vector<Vec2> run;
        std::size_t seen = 0;
        auto flush = [&] {
            if (run.size() >= 2) {
                summary_.inputPoints += run.size();
                ways_.push_back({std::move(run), rule, flags, 0, 0, &kept});
            }
            run.clear();
        };
        for (std::size_t i = 0; i + 1 < points.size(); ++i) {
            if (!segments_.insert(SegmentKey(points[i], points[i + 1])).second) {
                ++seen;
                flush();
                continue;
            }
            if (run.empty()) run.push_back(points[i]);
            run.push_back(points[i + 1]);
        }
        flush();
        const std::size_t total = points.size() - 1;
        if (seen == total) {
            ++report_.duplicateLines;
            report_.problems.push_back({source, "duplicate: every segment was imported before (the same way twice, or a relation over its ways)", true});
        } else if (seen > 0) {
            report_.duplicateLineSegments += seen;
            report_.problems.push_back({source, "overlaps earlier features (the shared segments removed, the rest imported)", false});
        }
    }

    // Splits the ways at nodes and merges chains; returns the number of curves to fit.
    std::size_t planCurves() {
        // Nodes: way ends and shared points.
        // A border point of a part (PartCut) is a node wherever a way passes through it.
        std::unordered_map<PointKey, int, PointHash> uses;
        for (const Piece& w : ways_)
            for (std::size_t i = 0; i < w.points.size(); ++i) uses[PointKey(w.points[i])] += (i == 0 || i + 1 == w.points.size()) ? 2 : 1;
        for (const PointKey& k : border_)
            if (const auto it = uses.find(k); it != uses.end()) it->second += 2;
        std::vector<Piece> pieces;
        for (const Piece& w : ways_) {
            Piece cur{{w.points.front()}, w.rule, w.flags, node(w.points.front()), 0, w.kept};
            for (std::size_t i = 1; i < w.points.size(); ++i) {
                cur.points.push_back(w.points[i]);
                if (uses[PointKey(w.points[i])] >= 2) {
                    cur.b = node(w.points[i]);
                    pieces.push_back(cur);
                    cur = Piece{{w.points[i]}, w.rule, w.flags, cur.b, 0, w.kept};
                }
            }
        }
        mergeChains(pieces);
        pieces_ = std::move(pieces);
        return std::size_t(std::count_if(pieces_.begin(), pieces_.end(), [](const Piece& p) { return p.alive; }));
    }

    // Fits the planned curves and adds them with their nodes.
    void buildCurves(Progress* progress) {
        std::vector<Piece> pieces = std::move(pieces_);
        std::vector<const std::vector<Vec2>*> polylines;
        for (const Piece& p : pieces)
            if (p.alive) polylines.push_back(&p.points);
        // Pieces have >= 2 points, no consecutive duplicates and finite coordinates (the reader
        // checked them), and importScene checked the tolerance: the fit cannot refuse them.
        std::vector<SplineFitResult> fits = fitAll(polylines, progress);
        std::size_t next = 0;
        for (const Piece& p : pieces) {
            if (!p.alive) continue;
            SplineFitResult& r = fits[next++];
            countFit(r);
            const MappingRule& rule = mapping_.rules[p.rule];
            Curve c;
            c.vertices = std::move(r.vertices);
            c.start = nodeId(p.a);
            c.end = nodeId(p.b);
            c.w = rule.w;
            c.wf = rule.wf;
            c.cls = rule.cls;
            c.flags = p.flags;
            keep(ElementKind::Curve, layer_.addCurve(std::move(c)), *p.kept);
            ++summary_.curvesByClass[rule.cls];
            if (p.flags & kBridge) ++summary_.bridges;
            if (p.flags & kTunnel) ++summary_.tunnels;
        }
        for (const Node& n : layer_.nodes) summary_.junctions += n.curves.size() >= 3;
        summary_.nodes = layer_.nodes.size();
    }

    // A point where this part's curves must stop, shared with the parts around (PartCut).
    void addBorder(Vec2 p) { border_.insert(PointKey(p)); }

    // The nodes made at border points (after buildCurves).
    std::vector<ElementId> borderNodes() const {
        std::vector<ElementId> out;
        for (std::size_t n = 0; n < nodeIds_.size(); ++n)
            if (nodeIds_[n] != kNoElement && border_.contains(PointKey(nodePoints_[n]))) out.push_back(nodeIds_[n]);
        return out;
    }

    // Queues an area (its rings closed, in scene metres); buildAreas() fits and adds them.
    void addArea(std::vector<std::vector<Vec2>> rings, std::size_t rule, const std::map<std::string, std::string>& kept,
                 const SourceRef& source) {
        if (!areaKeys_.insert(ringsKey(rings)).second) {
            ++report_.duplicateAreas;
            report_.problems.push_back({source, "duplicate: an area with the same rings was imported before", true});
            return;
        }
        for (const std::vector<Vec2>& ring : rings) summary_.inputPoints += ring.size() - 1;
        areas_.push_back({std::move(rings), rule, &kept});
    }

    std::size_t queuedRings() const {
        std::size_t n = 0;
        for (const QueuedArea& a : areas_) n += a.rings.size();
        return n;
    }

    void buildAreas(Progress* progress) {
        // A river layer's curves so far are its rivers: the axial curves its areas choose from.
        const AxialChooser axials(layer_.kind == LayerKind::Rivers ? layer_.curves.size() : 0, layer_);
        std::vector<const std::vector<Vec2>*> rings;
        for (const QueuedArea& a : areas_)
            for (const std::vector<Vec2>& ring : a.rings) rings.push_back(&ring);
        std::vector<SplineFitResult> fits = fitAll(rings, progress);
        std::size_t next = 0;
        for (const QueuedArea& a : areas_) {
            const MappingRule& r = mapping_.rules[a.rule];
            Area area;
            area.wf = r.wf;
            area.cls = r.cls;
            if (layer_.kind == LayerKind::Rivers) {
                area.axial = axials.choose(a.rings);
                ++report_.riverAreas;
                report_.riverAreasWithAxial += area.axial != kNoElement;
            }
            for (const std::vector<Vec2>& ring : a.rings) {
                SplineFitResult& fit = fits[next++];
                countFit(fit);
                const ElementId n = layer_.addNode(ring.front());
                Curve c;
                c.vertices = std::move(fit.vertices);
                c.start = c.end = n;
                c.wf = r.wf;
                const ElementId id = layer_.addCurve(std::move(c));
                area.loops.push_back({{id, false}});
            }
            summary_.holes += area.loops.size() - 1;
            keep(ElementKind::Area, layer_.addArea(std::move(area)), *a.kept);
            ++summary_.areasByClass[r.cls];
        }
        summary_.nodes = layer_.nodes.size();
        areas_.clear();
    }

private:
    // The axial curve of a river area (§4.1, §5.2): of the layer's first `count` curves (its
    // rivers, built before its areas), the one with the greatest length inside the area's rings
    // (even-odd, so holes are outside); none when no river runs through it. Each curve is measured
    // as a polyline of kSegmentsPerPiece chords per Bezier piece, a chord inside when its midpoint
    // is. Ties go to the lower curve id.
    class AxialChooser {
    public:
        AxialChooser(std::size_t count, const Layer& layer) {
            for (std::size_t c = 0; c < count; ++c) {
                Polyline p;
                p.points.push_back(layer.curves[c].vertices.front().p);
                forEachPiece(layer.curves[c].vertices, [&](const BezierPiece& b, std::size_t) {
                    for (int i = 1; i <= kSegmentsPerPiece; ++i) p.points.push_back(evaluate(b, double(i) / kSegmentsPerPiece));
                });
                p.box = boxOf(p.points);
                polylines_.push_back(std::move(p));
            }
        }

        ElementId choose(const std::vector<std::vector<Vec2>>& rings) const {
            const Box box = boxOf(rings.front());
            ElementId best = kNoElement;
            double bestInside = kMinInside;
            for (std::size_t c = 0; c < polylines_.size(); ++c) {
                const Polyline& p = polylines_[c];
                if (!p.box.intersects(box)) continue;
                double inside = 0.0;
                for (std::size_t i = 0; i + 1 < p.points.size(); ++i) {
                    const Vec2 mid = 0.5 * (p.points[i] + p.points[i + 1]);
                    if (box.contains(mid) && insideRings(rings, mid)) inside += glm::length(p.points[i + 1] - p.points[i]);
                }
                if (inside > bestInside) {
                    bestInside = inside;
                    best = ElementId(c);
                }
            }
            return best;
        }

    private:
        static constexpr int kSegmentsPerPiece = 8;
        static constexpr double kMinInside = 0.0;  // metres of a river inside the area to make it the axial curve (more than)
        struct Polyline {
            std::vector<Vec2> points;
            Box box;
        };
        static Box boxOf(const std::vector<Vec2>& pts) {
            Box b{pts.front(), pts.front()};
            for (const Vec2& p : pts) b = {glm::min(b.min, p), glm::max(b.max, p)};
            return b;
        }
        static bool insideRings(const std::vector<std::vector<Vec2>>& rings, Vec2 q) {
            bool inside = false;
            for (const std::vector<Vec2>& ring : rings)
                for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
                    if ((ring[i].y > q.y) != (ring[j].y > q.y) &&
                        q.x < (ring[j].x - ring[i].x) * (q.y - ring[i].y) / (ring[j].y - ring[i].y) + ring[i].x)
                        inside = !inside;
            return inside;
        }
        std::vector<Polyline> polylines_;
    };

    struct QueuedArea {
        std::vector<std::vector<Vec2>> rings;
        std::size_t rule;
        const std::map<std::string, std::string>* kept;
    };

    // Fits every polyline, on all cores (each fit is independent and deterministic, so the
    // results do not depend on the thread count).
    std::vector<SplineFitResult> fitAll(const std::vector<const std::vector<Vec2>*>& polylines, Progress* progress) const {
        std::vector<SplineFitResult> fits(polylines.size());
        tbb::parallel_for(std::size_t(0), polylines.size(), [&](std::size_t i) {
            fits[i] = fitSpline(*polylines[i], fit_);
            progressAdvance(progress);
        });
        return fits;
    }

    void countFit(const SplineFitResult& r) {
        std::size_t onCurve = 0;
        for (const Vertex& v : r.vertices) onCurve += v.onCurve;
        report_.outputVertices += r.vertices.size();
        report_.onCurveVertices += onCurve;
        report_.maxFitError = std::max(report_.maxFitError, r.maxError);
        summary_.outputVertices += r.vertices.size();
        summary_.onCurveVertices += onCurve;
        summary_.maxFitError = std::max(summary_.maxFitError, r.maxError);
    }

    void keep(ElementKind kind, ElementId id, const std::map<std::string, std::string>& kept) {
        if (!attributes_) return;
        for (const auto& [k, v] : kept) attributes_->push_back({id_, kind, id, k, v});
    }

    std::size_t node(Vec2 p) {
        const auto [it, added] = nodeIndex_.try_emplace(PointKey(p), nodePoints_.size());
        if (added) nodePoints_.push_back(p);
        return it->second;
    }
    ElementId nodeId(std::size_t n) {
        if (nodeIds_.size() <= n) nodeIds_.resize(n + 1, kNoElement);
        if (nodeIds_[n] == kNoElement) nodeIds_[n] = layer_.addNode(nodePoints_[n]);
        return nodeIds_[n];
    }

    // Merges pieces through nodes where exactly two pieces of the same rule and flags meet (for
    // rivers: one ending and one starting there).
    void mergeChains(std::vector<Piece>& pieces) {
        std::vector<std::vector<std::size_t>> at(nodePoints_.size());
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            at[pieces[i].a].push_back(i);
            at[pieces[i].b].push_back(i);
        }
        const bool rivers = layer_.kind == LayerKind::Rivers;
        for (std::size_t n = 0; n < at.size(); ++n) {
            std::vector<std::size_t> live;
            for (std::size_t i : at[n])
                if (pieces[i].alive) live.push_back(i);
            if (live.size() != 2 || live[0] == live[1] || border_.contains(PointKey(nodePoints_[n]))) continue;
            Piece& p = pieces[live[0]];
            Piece& q = pieces[live[1]];
            if (p.rule != q.rule || p.flags != q.flags || *p.kept != *q.kept) continue;
            // Orient so that p ends at n and q starts at n.
            Piece* first = &p;
            Piece* second = &q;
            if (p.b != n) std::swap(first, second);
            if (first->b != n || second->a != n) {
                if (rivers) continue;  // flows that meet head to head or tail to tail stay apart
                if (first->b != n) {
                    std::reverse(first->points.begin(), first->points.end());
                    std::swap(first->a, first->b);
                }
                if (second->a != n) {
                    std::reverse(second->points.begin(), second->points.end());
                    std::swap(second->a, second->b);
                }
            }
            if (first->b != n || second->a != n) continue;
            first->points.insert(first->points.end(), second->points.begin() + 1, second->points.end());
            first->b = second->b;
            second->alive = false;
            ++report_.chainsMerged;
            // The merged piece now ends where `second` ended: update that node's list.
            for (std::size_t& i : at[first->b])
                if (&pieces[i] == second) i = std::size_t(first - pieces.data());
        }
    }

    Layer& layer_;
    LayerId id_;
    LayerSummary& summary_;
    const FeatureMapping& mapping_;
    const SplineFitParams& fit_;
    NetworkReport& report_;
    std::vector<ElementAttribute>* attributes_;
    std::vector<Piece> ways_;
    std::vector<Piece> pieces_;  // planned curves
    std::vector<QueuedArea> areas_;
    std::unordered_set<SegmentKey, SegmentHash> segments_;
    std::unordered_set<PointKey, PointHash> border_;
    std::unordered_set<std::vector<std::uint64_t>, KeyHash> areaKeys_;
    std::unordered_map<PointKey, std::size_t, PointHash> nodeIndex_;
    std::vector<Vec2> nodePoints_;
    std::vector<ElementId> nodeIds_;
};

// The stretches of `pts` whose segments go to `cut`'s part, as ways of `builder`; every point of a
// segment between two parts is a border point.
void addWayPieces(LayerBuilder& builder, const PartCut& cut, const std::vector<Vec2>& pts, std::size_t rule, std::uint16_t flags,
                  const std::map<std::string, std::string>& kept, const SourceRef& source) {
    std::vector<Vec2> run;
    const auto flush = [&] {
        if (run.size() >= 2) builder.addWay(run, rule, flags, kept, source);
        run.clear();
    };
    int a = cut.grid.partOf(pts.front());
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        const int b = cut.grid.partOf(pts[i + 1]);
        if (a != b) {
            builder.addBorder(pts[i]);
            builder.addBorder(pts[i + 1]);
        }
        if (std::min(a, b) == cut.part) {
            if (run.empty()) run.push_back(pts[i]);
            run.push_back(pts[i + 1]);
        } else {
            flush();
        }
        a = b;
    }
    flush();
}

// The part an area goes to: that of its outer ring's least point (x, then y), whatever its start.
int areaPart(const PartGrid& grid, const std::vector<Vec2>& outer) {
    Vec2 least = outer.front();
    for (const Vec2& p : outer)
        if (std::tie(p.x, p.y) < std::tie(least.x, least.y)) least = p;
    return grid.partOf(least);
}

}  // namespace

int PartGrid::partOf(Vec2 p) const {
    const Vec2 f = (p - square.min) / square.size() * double(side);
    // Clamped as a double first: a point far outside the square must not overflow the int.
    const auto index = [&](double v) { return std::isfinite(v) ? int(std::clamp(std::floor(v), 0.0, double(side - 1))) : 0; };
    return index(f.y) * side + index(f.x);
}

Box PartGrid::partBox(int part) const {
    const Vec2 cell = square.size() / double(side);
    const Vec2 min = square.min + cell * Vec2(part % side, part / side);
    return {min, min + cell};
}

Scene buildScene(const VectorData& data, const FeatureMapping& mapping, const SceneFrame& frame, const Box& extent,
                 const std::function<bool(glm::dvec2)>& insideDem, const SplineFitParams& fit, NetworkReport& report,
                 std::vector<ElementAttribute>* attributes, Progress* progress, PartCut* cut) {
    Scene scene;
    scene.extent = extent;
    report = {};
    for (const MappingLayer& ml : mapping.layers) {
        scene.layers.emplace_back();
        scene.layers.back().name = ml.name;
        scene.layers.back().kind = ml.kind;
        report.layers.emplace_back();
        report.layers.back().name = ml.name;
        report.layers.back().kind = ml.kind;
    }
    auto outside = [&](const std::vector<glm::dvec2>& pts) {
        if (!insideDem) return false;
        for (const glm::dvec2& p : pts)
            if (!insideDem(p)) return true;
        return false;
    };
    std::vector<std::unique_ptr<LayerBuilder>> builders;
    for (std::size_t l = 0; l < scene.layers.size(); ++l)
        builders.push_back(std::make_unique<LayerBuilder>(scene.layers[l], LayerId(l), report.layers[l], mapping, fit, report, attributes));
    // Ways before the parts of multi-line features (relations over those ways), in file order.
    std::vector<const RawLine*> lines;
    for (const RawLine& line : data.lines) lines.push_back(&line);
    std::stable_partition(lines.begin(), lines.end(), [](const RawLine* l) { return !l->inMulti; });
    // With a cut, a feature's problems are reported by one part: that of its first point.
    const auto reports = [&](const glm::dvec2& first) { return !cut || cut->grid.partOf(frame.forward(first)) == cut->part; };
    for (const RawLine* line : lines) {
        if (outside(line->lonLat)) {
            if (reports(line->lonLat.front())) report.problems.push_back({line->source, "outside the DEM", true});
            continue;
        }
        const std::vector<Vec2> pts = project(frame, line->lonLat);
        if (pts.size() < 2) continue;
        LayerBuilder& builder = *builders[mapping.rules[line->rule].layer];
        if (cut) addWayPieces(builder, *cut, pts, line->rule, line->flags, line->kept, line->source);
        else builder.addWay(pts, line->rule, line->flags, line->kept, line->source);
    }
    for (const RawArea& area : data.areas) {
        bool out = false;
        for (const auto& ring : area.rings) out = out || outside(ring);
        if (out) {
            if (reports(area.rings.front().front())) report.problems.push_back({area.source, "outside the DEM", true});
            continue;
        }
        std::vector<std::vector<Vec2>> rings;
        for (const auto& ring : area.rings) {
            rings.push_back(project(frame, ring));
            if (rings.back().back() != rings.back().front()) rings.back().push_back(rings.back().front());
        }
        if (cut && areaPart(cut->grid, rings.front()) != cut->part) continue;
        bool degenerate = false;
        for (const auto& ring : rings) degenerate = degenerate || ring.size() < 4;
        if (degenerate) {
            report.problems.push_back({area.source, "degenerate ring after projection", true});
            continue;
        }
        builders[mapping.rules[area.rule].layer]->addArea(std::move(rings), area.rule, area.kept, area.source);
    }
    std::size_t curves = 0;
    for (auto& b : builders) curves += b->planCurves() + b->queuedRings();
    progressBegin(progress, "fitting splines", curves, "curves");
    for (auto& b : builders) b->buildCurves(progress);
    for (auto& b : builders) b->buildAreas(progress);
    progressEnd(progress);
    if (cut) {
        cut->borderNodes.clear();
        for (auto& b : builders) cut->borderNodes.push_back(b->borderNodes());
    }
    for (const LayerSummary& l : report.layers) report.inputPoints += l.inputPoints;
    return scene;
}

}  // namespace lacet
