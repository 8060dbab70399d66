// A snow profile as a pit gives it: its layers from the surface down, the density samples taken in
// it, the slope, and the propagation saw tests done in it. What the formats (CAAML, a layer table)
// hold, in SI units; what is inferred from it (densities from hand hardness, moduli, strengths) is
// profile/layer_properties.h. Knows no module but util.
#pragma once

#include "profile/hand_hardness.h"

#include <optional>
#include <string>
#include <vector>

namespace anticrack::profile
{
  /// What a layer is for the saw test: above the weak layer (slab), the weak layer, or below it.
  enum class LayerRole
  {
    unspecified,
    slab,
    weak,
    base
  };
  const char *role_name(LayerRole role);

  struct ProfileLayer
  {
    double depth_top_m = 0; ///< from the snow surface, positive down
    double thickness_m = 0;
    std::string grain_form;                  ///< primary grain form code (IACS, Fierz et al. 2009): "FC", "RGxf"; empty if not observed
    std::optional<double> grain_size_mm;     ///< average grain size
    std::optional<HandHardness> hardness;    ///< the layer's hand hardness (its top's when it has two)
    std::optional<HandHardness> hardness_bottom; ///< a second reading at the layer's bottom (CAAML hardnessBottom)
    std::optional<double> density_kg_m3;     ///< measured in the layer (a layer table's column)
    LayerRole role = LayerRole::unspecified; ///< a layer table's `role`
    double depth_bottom_m() const { return depth_top_m + thickness_m; }
  };

  /// A density measurement over a depth interval (a CAAML density profile's sample: a 100 cm^3
  /// cutter is 4 cm tall).
  struct DensitySample
  {
    double depth_top_m = 0, thickness_m = 0, density_kg_m3 = 0;
  };

  /// A propagation saw test as the observer recorded it (Gauthier & Jamieson 2008; the field
  /// protocol of Greene et al. 2016): the failed layer's depth, how the crack ran (End: to the end of
  /// the column; Arr: it arrested; SF: the slab fractured), the cut length at which it ran (read by
  /// eye) and the column's length.
  struct SawTestObservation
  {
    double failed_depth_m = 0;
    std::string propagation; ///< "End", "Arr" or "SF"
    double cut_length_m = 0, column_length_m = 0;
    std::string comment;
  };

  struct SnowProfile
  {
    std::string file;   ///< where it was read from
    std::string format; ///< the reader's name ("CAAML v6.0.3 SnowProfileIACS", "layer table")
    std::string id;     ///< the pit's identifier where the file gives one
    std::optional<double> slope_angle_deg;
    std::vector<ProfileLayer> layers; ///< from the surface down, contiguous
    std::vector<DensitySample> density_samples;
    std::vector<SawTestObservation> saw_tests;
    double height_m() const { return layers.empty() ? 0.0 : layers.back().depth_bottom_m(); }
    /// The layer holding `depth` (a layer's top belongs to it; the bottom of the last layer to it); -1 if none.
    int layer_at_depth(double depth_m) const;
  };
} // namespace anticrack::profile
