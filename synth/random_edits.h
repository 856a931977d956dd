#pragma once
// Random edits of every kind, for the randomized invariant tests and `lacet check incremental`.
// Deterministic for a given generator state.

#include <cstdint>
#include <random>
#include <string>

#include "model/changeset.h"
#include "model/graph.h"

namespace lacet {

enum class EditKind : std::uint8_t {
    MoveVertex, InsertVertex, DeleteVertex, MoveNode, AddNode, DeleteNode, AddCurve, DeleteCurve,
    AddArea, DeleteArea, SetCurveWidth, SetCurveClass, SetAreaClass, SetAreaFootprint,
    SetRoundabout,  // a roundabout made at a road node, or removed (a refused radius edits nothing)
    SetCurveFlags,  // a road made a bridge, a tunnel or a ford, or back
    Count
};
std::string_view toString(EditKind kind);

// Uniform double in [0, 1) from 53 bits of the generator (portable, unlike
// std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng);

struct RandomEdit {
    EditKind kind = EditKind::MoveVertex;
    Changeset changeset;  // empty when no element of the required kind existed
};

// Applies one random edit to the scene. `reach` (metres) bounds how far points move and how
// large new elements are.
RandomEdit applyRandomEdit(Scene& scene, std::mt19937_64& rng, double reach);

}  // namespace lacet
