#include "fem/scene/layers.h"

#include <algorithm>
#include <cmath>

namespace anticrack::fem
{
  unsigned int n_layers(const Snowpack &snowpack)
  {
    return layer_first_slab + snowpack.slab_layers.size();
  }

  unsigned int slab_layer_id(const Snowpack &snowpack, unsigned int slab_index)
  {
    return layer_first_slab + (snowpack.slab_layers.size() - 1 - slab_index);
  }

  unsigned int slab_index(const Snowpack &snowpack, unsigned int layer_id)
  {
    return snowpack.slab_layers.size() - 1 - (layer_id - layer_first_slab);
  }

  const Layer &layer_of(const Snowpack &snowpack, unsigned int layer_id)
  {
    if (layer_id == layer_substratum)
      return snowpack.substratum;
    if (layer_id == layer_weak)
      return snowpack.weak_layer;
    return snowpack.slab_layers[slab_index(snowpack, layer_id)];
  }

  std::vector<double> layer_tops(const Snowpack &snowpack)
  {
    std::vector<double> tops{snowpack.substratum.thickness, snowpack.weak_layer_top()};
    double top = snowpack.weak_layer_top();
    for (auto layer = snowpack.slab_layers.rbegin(); layer != snowpack.slab_layers.rend(); ++layer)
      tops.push_back(top += layer->thickness);
    return tops;
  }

  unsigned int layer_id_at(const std::vector<double> &tops, double z)
  {
    unsigned int id = 0;
    while (id + 1 < tops.size() && z > tops[id])
      ++id;
    return id;
  }

  unsigned int element_rows(const SnowpackScene &scene, unsigned int layer_id)
  {
    const MeshParameters &m = scene.mesh;
    if (layer_id == layer_weak)
      return m.weak_layer_elements;
    const double thickness = layer_of(scene.snowpack, layer_id).thickness;
    const double target = layer_id == layer_substratum ? m.substratum_element_height : m.slab_element_height;
    return std::max(1u, (unsigned int)std::ceil(thickness / target - 1e-9));
  }

  double element_height(const SnowpackScene &scene, unsigned int layer_id)
  {
    return layer_of(scene.snowpack, layer_id).thickness / element_rows(scene, layer_id);
  }

  unsigned int column_count(const SnowpackScene &scene)
  {
    return std::max(4u, static_cast<unsigned int>(std::lround(scene.pst.column_length / scene.mesh.element_length)));
  }
} // namespace anticrack::fem
