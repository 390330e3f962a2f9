#pragma once
// Fictitious loading layers (docs/mesher.md, "Loading layers"): rows of
// lattice squares outside the plate, beyond straight outer edges, through
// which scenes load the body instead of through a rigid strip inside it.
#include <string>
#include <vector>

#include "material_boundary.hpp"
#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

// The edges that can carry a layer: the sides of the bounding box, named as
// the boundary sets name them.
inline const std::vector<std::string> loading_layer_edges = {"left", "right", "bottom", "top"};

// Name of the particle set holding the layer beyond `edge`.
std::string loading_layer_set_name(const std::string& edge);

// "top,bottom" -> {"top", "bottom"}. Throws pd::Error naming `option` and the
// value for an empty list, an unknown edge or one given twice.
std::vector<std::string> parse_loading_layer_edges(const std::string& text, const std::string& option);

// Number of lattice rows a layer `depth` deep takes: depth / dx rounded up.
long loading_layer_rows(double depth, double spacing);

// Appends ceil(depth / dx) rows of dx squares (region uniform_square, volume
// dx^2, the plate's lattice) beyond every straight outer curve lying on each
// named side of the bounding box, and grows the particle set's bounding box
// by the layers. Call before sorting and building families; horizon and
// material are set like the other particles' by the caller (all zero here).
// Throws pd::Error naming `option` when a side has no straight curve, or a
// curve's ends do not lie on lattice lines (its layer would not be squares).
void append_loading_layers(ParticleSet& particles, const PlateGeometry& geometry,
                           const std::vector<std::string>& edges, double depth, const std::string& option);

// The boundary that decides which bonds exist, with the layers counted as
// material: the outer loop goes round each layer, so that bonds between the
// layer and the body are kept while notches and holes still cut theirs.
MaterialBoundary material_boundary_with_layers(const PlateGeometry& geometry, double spacing, double horizon,
                                               const std::vector<std::string>& edges, double depth);

// True for a particle outside the plate's bounding box, i.e. of a layer.
bool in_loading_layer(const ParticleSet& particles, const PlateGeometry& geometry, std::size_t i);

// After add_boundary_sets: takes the layer particles out of the plate's sets
// (those stay in-body strips) and adds one set per layer,
// loading_layer_set_name(edge). Throws pd::Error if a set of that name exists.
void add_loading_layer_sets(ParticleSet& particles, const PlateGeometry& geometry,
                            const std::vector<std::string>& edges);

}  // namespace pd
