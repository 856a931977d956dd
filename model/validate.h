#pragma once
// Validation of a scene's root graph: rejects NaN/Inf and absurd coordinates, dangling
// references, adjacency lists that disagree with the curves and areas, malformed splines, open
// area loops and a non-square extent, with a message naming the layer, the element and the reason.

#include <stdexcept>
#include <string>
#include <vector>

#include "model/graph.h"

namespace lacet {

struct Problem {
    std::string where;   // e.g. "layer 'roads' curve 12"
    std::string reason;  // e.g. "vertex 3 has a non-finite coordinate"
};

class ValidationError : public std::runtime_error {
public:
    explicit ValidationError(std::vector<Problem> problems);
    const std::vector<Problem>& problems() const { return problems_; }

private:
    std::vector<Problem> problems_;
};

// Every problem of the scene, in layer and id order; empty when the scene is valid.
std::vector<Problem> validate(const Scene& scene);
// Throws ValidationError listing every problem, if any.
void validateOrThrow(const Scene& scene);

// Largest coordinate magnitude accepted (metres): far beyond any projected CRS (the Earth's
// circumference is 4e7 m), and small enough that squared distances stay finite.
constexpr double kMaxCoordinate = 1.0e9;

// Checks of single values and vertex chains, shared with the edit commands.
// True when both coordinates are finite and within kMaxCoordinate.
bool isFinite(Vec2 p);
// Empty when `v` is a well-formed spline: >= 2 vertices, on-curve ends, <= 2 controls in a row,
// finite coordinates. Otherwise the reason.
std::string splineProblem(const std::vector<Vertex>& v);

}  // namespace lacet
