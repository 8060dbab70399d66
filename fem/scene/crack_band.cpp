#include "fem/scene/crack_band.h"

#include "fem/scene/layers.h"

namespace anticrack::fem
{
  CamClayParameters cam_clay_parameters(const Layer &layer, double band_height)
  {
    const ContinuumMaterial &m = layer.material;
    CamClayParameters parameters;
    parameters.set_elastic_moduli(m.youngs_modulus, m.poisson_ratio);
    parameters.M = m.M;
    parameters.beta = m.beta;
    parameters.p0_initial = m.p0;
    parameters.hardening_factor = m.hardening_factor;
    if (m.reference_thickness > 0)
      parameters.hardening_factor *= band_height / m.reference_thickness;
    parameters.law = m.hardening_law == "signed" ? HardeningLaw::signed_volumetric : HardeningLaw::collapse;
    parameters.p0_floor = residual_p0_floor(m.p0, m.residual_strength_ratio);
    if (layer.collapse_height > 0)
    {
      parameters.densification_strain = layer.collapse_height / band_height;
      parameters.densification_modulus = layer.densification_modulus;
    }
    parameters.check();
    return parameters;
  }

  double band_height(const SnowpackScene &scene, unsigned int layer_id)
  {
    // The weak layer collapses as one band through its thickness (fem/model/snowpack_model.h).
    if (scene.analysis.crack_band && layer_id != layer_weak)
      return element_height(scene, layer_id);
    return layer_of(scene.snowpack, layer_id).thickness;
  }
} // namespace anticrack::fem
