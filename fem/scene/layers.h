// The layers of the discretised snowpack by layer id, the cells' material id: 0 the substratum,
// 1 the weak layer, 2, 3, ... the slab layers from the bottom up (a scene lists the slab layers top
// first, as a snow profile is read; docs/physics.md §3). The one place that maps layer ids to the
// scene's layers and says how many element rows of which height each layer gets.
#pragma once

#include "fem/scene/snowpack_scene.h"

#include <vector>

namespace anticrack::fem
{
  /// Material ids of the cells.
  enum LayerId : unsigned int
  {
    layer_substratum = 0,
    layer_weak = 1,
    layer_first_slab = 2 ///< slab layers from the bottom up: 2, 3, ...
  };

  /// Number of layer ids: substratum (even of thickness 0), weak layer and every slab layer.
  unsigned int n_layers(const Snowpack &snowpack);

  /// Layer id of slab layer `slab_index` as the scene lists it (0: the top layer).
  unsigned int slab_layer_id(const Snowpack &snowpack, unsigned int slab_index);

  /// Slab index (as the scene lists them, 0: the top layer) of the slab layer of id `layer_id`.
  unsigned int slab_index(const Snowpack &snowpack, unsigned int layer_id);

  /// The layer of layer id `layer_id`.
  const Layer &layer_of(const Snowpack &snowpack, unsigned int layer_id);

  /// Height of the top of each layer above the model base, by layer id [m].
  std::vector<double> layer_tops(const Snowpack &snowpack);

  /// Layer id of the element row whose centre is at height `z` above the model base, from
  /// layer_tops(): the lowest layer whose top lies at or above z.
  unsigned int layer_id_at(const std::vector<double> &tops, double z);

  /// Element rows through layer `layer_id`: `Weak layer elements` in the weak layer, elsewhere the
  /// fewest rows (at least one) no higher than the layer's target element height.
  unsigned int element_rows(const SnowpackScene &scene, unsigned int layer_id);

  /// Height normal to the slope of the elements of layer `layer_id`, thickness / element_rows() [m].
  double element_height(const SnowpackScene &scene, unsigned int layer_id);

  /// Element columns along the slope: the column length over `Element length`, rounded, at least 4.
  unsigned int column_count(const SnowpackScene &scene);
} // namespace anticrack::fem
