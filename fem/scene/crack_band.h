// The constitutive parameters of each layer of the discretised snowpack, with the softening
// regularised over the band in which it localises (docs/physics.md §2 "Regularisation").
// The band must dissipate and collapse what the calibrated layer of reference thickness h_ref does:
//   ξ_b = ξ h_b / h_ref                 (the same plastic closure h_b Δα_b to the residual),
//   ε_d,b = collapse height / h_b       (the band closes by the layer's collapse height),
// with the p0 floor from the residual strength ratio. The weak layer's band is its thickness: its
// inner nodes are tied so that it deforms as one band (fem/model/snowpack_model.h). Other cohesive
// Cam-Clay layers soften in a crack band of one element row (Bažant & Oh 1983), h_b = h_e, or over
// their whole thickness with Analysis/Crack band regularisation = false.
#pragma once

#include "fem/material/cohesive_cam_clay.h"
#include "fem/scene/snowpack_scene.h"

namespace anticrack::fem
{
  /// Cam-Clay parameters of a cohesive Cam-Clay layer whose softening localises in a band of
  /// height `band_height` [m] (see above). Throws std::invalid_argument (via check()) when the
  /// result is out of range, e.g. a band thinner than the collapse height.
  CamClayParameters cam_clay_parameters(const Layer &layer, double band_height);

  /// The band height cam_clay_parameters() gets for layer `layer_id` (fem/scene/layers.h): the
  /// weak layer's thickness; for the others their element height with the crack band, their
  /// thickness without [m].
  double band_height(const SnowpackScene &scene, unsigned int layer_id);
} // namespace anticrack::fem
