// The constitutive parameters of each layer of the discretised snowpack: the crack band
// regularisation of softening layers (Bažant & Oh 1983; docs/physics.md §2 "Regularisation").
// Softening localises in one element row of height h_e normal to the slope, which must dissipate
// and collapse what the calibrated layer of reference thickness h_ref does, so
//   ξ_e = ξ h_e / h_ref                 (same plastic displacement h_e Δα_e to the residual),
//   ε_d,e = collapse height / h_e       (the row closes by the layer's collapse height),
// with the p0 floor from the residual strength ratio. Without the regularisation (Analysis/Crack
// band regularisation = false, the local model) the band is the whole layer.
#pragma once

#include "fem/material/cohesive_cam_clay.h"
#include "fem/scene/snowpack_scene.h"

namespace anticrack::fem
{
  /// Cam-Clay parameters of a cohesive Cam-Clay layer whose softening localises in a band of
  /// height `band_height` [m] (see above). Throws std::invalid_argument (via check()) when the
  /// result is out of range, e.g. a band thinner than the collapse height.
  CamClayParameters cam_clay_parameters(const Layer &layer, double band_height);

  /// The band height cam_clay_parameters() gets for layer `layer_id` (fem/model/layers.h): its
  /// element height with the crack band, its thickness without [m].
  double band_height(const SnowpackScene &scene, unsigned int layer_id);
} // namespace anticrack::fem
