#pragma once
// How many bonds each particle of a meshed grid will get, estimated from the
// particles' positions and horizons before the families are built. The
// estimate before meshing assumes cells of about the spacing; a hole much
// smaller than the spacing forces free cells far smaller than that around
// it, each of which keeps the horizon m dx, so the families, not the
// particle count, blow up (docs/mesher.md, "Size once meshed"). Counting
// costs O(N): a summed-area table of particles per lattice cell.
#include <vector>

#include "particle_file.hpp"

namespace pd {

// Per particle: the particles whose centroid lies within horizon_i plus half
// its own cell's diagonal of x_i (the cells that can meet its disk, when its
// neighbours are about its size), the particle itself left out. The density
// is taken as uniform within each cell of a lattice of about the spacing, so
// the estimate follows the local density at that scale; holes narrower than
// a lattice cell and the bond rule at voids are not seen (the bonds that
// cross such holes are counted: 17 to 19 % above the file for plates of
// many, docs/mesher.md, "Size once meshed"). Squares of side dx with the nominal horizon are scaled to the
// count of the cells a disk meets (by the disk's area alone 42.2 for 44 at
// m = 3, 68.6 for 68 at m = 4), so an interior square gets its family exactly.
// The disk is counted as a stack of strips of its own area, so an edge cuts
// it as it cuts the disk: the particle file's size within 1 % on small plates
// of mostly boundary cells (C1 at 0.5 mm) and large ones alike.
std::vector<double> estimate_family_sizes(const ParticleSet& particles);

}  // namespace pd
