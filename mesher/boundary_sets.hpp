#pragma once
// Boundary sets, for loads in scenes: the particles within a distance of
// boundary curves (docs/mesher.md, "Boundary sets").
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

// Adds the sets, each holding the particles within `distance` of its curves
// and seen from them through the material (the straight line to the nearest
// point of the curve does not cross a void: a particle on the far side of a
// notch narrower than `distance` is not near the notch's other face):
//   left, right, bottom, top: the straight boundary curves lying on that side
//     of the plate's bounding box (the whole side for a rectangle; the parts
//     beside a notch; no set if no curve lies there, e.g. a round plate);
//   hole_1, hole_2, ...: the holes' curves;
//   every named physical curve group of the geometry file (a group with the
//     name of an automatic set replaces it).
// Returns warnings: a group that replaces an automatic set without a
// particle in common with it (`Physical Curve("left")` on the right edge).
std::vector<std::string> add_boundary_sets(ParticleSet& particles, const PlateGeometry& geometry, double distance);

}  // namespace pd
