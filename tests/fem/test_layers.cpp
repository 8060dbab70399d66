// fem/scene/layers.h: layer ids <-> the scene's layers (slab layers listed top first, ids from the
// bottom up), which layer an element row belongs to, and the element rows of each layer.
#include "fem/scene/crack_band.h"
#include "fem/scene/layers.h"

#include <gtest/gtest.h>

namespace
{
  using namespace anticrack::fem;

  SnowpackScene three_slab_layers()
  {
    SnowpackScene scene;
    Snowpack &s = scene.snowpack;
    for (const double thickness : {0.1, 0.25, 0.05}) // top first
    {
      Layer layer;
      layer.thickness = thickness;
      s.slab_layers.push_back(layer);
    }
    s.weak_layer.thickness = 0.02;
    s.substratum.thickness = 0.12;
    scene.mesh.weak_layer_elements = 4;
    scene.mesh.slab_element_height = 0.04;
    scene.mesh.substratum_element_height = 0.05;
    return scene;
  }

  TEST(FemLayers, SlabLayersAreNumberedFromTheBottomUp)
  {
    const SnowpackScene scene = three_slab_layers();
    const Snowpack &s = scene.snowpack;
    EXPECT_EQ(n_layers(s), 5u);
    EXPECT_EQ(slab_layer_id(s, 0), 4u); // the top layer
    EXPECT_EQ(slab_layer_id(s, 2), 2u); // the layer on the weak layer
    for (unsigned int k = 0; k < s.slab_layers.size(); ++k)
    {
      EXPECT_EQ(slab_index(s, slab_layer_id(s, k)), k);
      EXPECT_EQ(&layer_of(s, slab_layer_id(s, k)), &s.slab_layers[k]);
    }
    EXPECT_EQ(&layer_of(s, layer_substratum), &s.substratum);
    EXPECT_EQ(&layer_of(s, layer_weak), &s.weak_layer);
  }

  TEST(FemLayers, RowCentresFallIntoTheirLayers)
  {
    const SnowpackScene scene = three_slab_layers();
    const std::vector<double> tops = layer_tops(scene.snowpack);
    ASSERT_EQ(tops.size(), 5u);
    EXPECT_DOUBLE_EQ(tops[1], 0.14);
    EXPECT_DOUBLE_EQ(tops.back(), scene.snowpack.total_thickness());
    EXPECT_EQ(layer_id_at(tops, 0.01), layer_substratum);
    EXPECT_EQ(layer_id_at(tops, 0.13), layer_weak);
    EXPECT_EQ(layer_id_at(tops, 0.16), 2u);
    EXPECT_EQ(layer_id_at(tops, 0.30), 3u);
    EXPECT_EQ(layer_id_at(tops, 0.50), 4u);
  }

  TEST(FemLayers, ElementRowsAreNoHigherThanTheTargets)
  {
    const SnowpackScene scene = three_slab_layers();
    EXPECT_EQ(element_rows(scene, layer_substratum), 3u); // 0.12 m in rows of <= 0.05 m
    EXPECT_EQ(element_rows(scene, layer_weak), 4u);
    EXPECT_EQ(element_rows(scene, 2), 2u);                // 0.05 m
    EXPECT_EQ(element_rows(scene, 3), 7u);                // 0.25 m
    EXPECT_EQ(element_rows(scene, 4), 3u);                // 0.1 m: 2.5 rows of 4 cm, so 3
    EXPECT_DOUBLE_EQ(element_height(scene, layer_weak), 0.005);
    EXPECT_DOUBLE_EQ(element_height(scene, 2), 0.025);
  }

  // The weak layer is one band through its thickness, whatever its rows (its inner nodes are tied);
  // another layer softens in one element row, or over its thickness without the crack band.
  TEST(FemCrackBand, TheWeakLayerIsOneBandOtherLayersOneElementRow)
  {
    SnowpackScene scene = three_slab_layers();
    EXPECT_DOUBLE_EQ(band_height(scene, layer_weak), 0.02);
    EXPECT_DOUBLE_EQ(band_height(scene, 2), 0.025);
    scene.analysis.crack_band = false;
    EXPECT_DOUBLE_EQ(band_height(scene, layer_weak), 0.02);
    EXPECT_DOUBLE_EQ(band_height(scene, 2), 0.05);
  }
} // namespace
