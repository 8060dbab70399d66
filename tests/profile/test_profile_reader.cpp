// The profile readers on the 75 real SnowPilot pits of data/field_psts (every one read, its saw tests
// equal to the independent extraction in snowpilot_psts.csv, one pit checked layer by layer against
// its file by hand), and every refusal: a file that is not a profile, another schema, units other
// than the schema's, torn XML, a 50 MB file, overlapping or negative layers, a failed layer outside
// the profile, and the layer table's unit and value errors.
#include "profile/layer_properties.h"
#include "profile/profile_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace
{
  namespace fs = std::filesystem;
  using namespace anticrack::profile;

  const fs::path field_pits = fs::path(ANTICRACK_SOURCE_DIR) / "data" / "field_psts";

  std::string read(const fs::path &file)
  {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  /// A copy of a field pit with `from` replaced by `to` (once), in the test's temporary folder.
  fs::path edited(const std::string &pit, const std::string &from, const std::string &to, const std::string &name)
  {
    std::string text = read(field_pits / "snowpilot" / pit);
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from << " not in " << pit;
    if (at != std::string::npos)
      text.replace(at, from.size(), to);
    const fs::path file = fs::temp_directory_path() / ("anticrack_profile_" + name);
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

  /// The message of the ProfileError that reading `file` throws ("" if it reads).
  std::string refusal(const fs::path &file)
  {
    try
    {
      read_profile(file.string());
    }
    catch (const ProfileError &e)
    {
      return e.what();
    }
    return "";
  }

  void expect_refused(const fs::path &file, const std::vector<std::string> &needles)
  {
    const std::string message = refusal(file);
    ASSERT_FALSE(message.empty()) << file << " was read";
    EXPECT_NE(message.find(file.string()), std::string::npos) << "the message does not name the file: " << message;
    for (const std::string &needle : needles)
      EXPECT_NE(message.find(needle), std::string::npos) << "`" << needle << "` not in: " << message;
  }

  std::vector<std::string> split(const std::string &line)
  {
    std::vector<std::string> fields;
    std::string field;
    std::istringstream in(line);
    while (std::getline(in, field, ','))
      fields.push_back(field);
    if (!fields.empty() && !fields.back().empty() && fields.back().back() == '\r')
      fields.back().pop_back(); // the CSV has CRLF line ends
    return fields;
  }
} // namespace

TEST(ProfileReader, EveryFieldPitIsReadWithItsSawTests)
{
  // snowpilot_psts.csv was extracted from the same files by another program (Python's ElementTree):
  // pit, ..., outcome, cut_cm, column_cm, file; the failed layer's depth is wl_depth_cm only where
  // the failure is on a layer's top, so the depth is checked against the file's own failedOn.
  std::ifstream csv(field_pits / "snowpilot_psts.csv");
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = split(line);
  const auto column = [&](const char *name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  std::map<std::string, std::vector<std::vector<std::string>>> rows_of_file;
  while (std::getline(csv, line))
    if (!line.empty())
      rows_of_file[split(line)[column("file")]].push_back(split(line));

  int pits = 0, tests = 0, without_density = 0;
  for (const auto &entry : fs::directory_iterator(field_pits / "snowpilot"))
  {
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    SnowProfile p;
    ASSERT_NO_THROW(p = read_profile(entry.path().string()));
    ++pits;
    EXPECT_EQ(p.format, "CAAML v6.0 SnowProfileIACS");
    EXPECT_GE(p.layers.size(), 4u);
    const auto &rows = rows_of_file[name];
    ASSERT_EQ(p.saw_tests.size(), rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
      EXPECT_EQ(p.saw_tests[k].propagation, rows[k][column("outcome")]);
      EXPECT_NEAR(p.saw_tests[k].cut_length_m, std::stod(rows[k][column("cut_cm")]) / 100, 1e-12);
      EXPECT_NEAR(p.saw_tests[k].column_length_m, std::stod(rows[k][column("column_cm")]) / 100, 1e-12);
      const double slope = rows[k][column("slope_deg")].empty() ? NAN : std::stod(rows[k][column("slope_deg")]);
      if (std::isnan(slope))
        EXPECT_FALSE(p.slope_angle_deg.has_value());
      else
        EXPECT_EQ(p.slope_angle_deg.value_or(NAN), slope);
      ++tests;
    }
    // Every layer gets a density where the laws allow one (measured, or Geldsetzer & Jamieson's classes).
    for (std::size_t k = 0; k < p.layers.size(); ++k)
      try
      {
        const LayerProperties props = layer_properties(p, k, modulus_laws().front(), 0.25);
        EXPECT_GE(props.density.value, lightest_snow_density);
        EXPECT_LE(props.density.value, ice_density);
      }
      catch (const ProfileError &e)
      {
        // only a layer in which nothing was measured, and that a cited law does not cover or that
        // has no hardness; named
        const std::string message = e.what();
        EXPECT_TRUE(message.find("cannot be inferred") != std::string::npos ||
                    message.find("no hand hardness") != std::string::npos)
          << message;
        EXPECT_NE(message.find("layer " + std::to_string(k + 1) + " "), std::string::npos) << message;
        ++without_density;
      }
  }
  EXPECT_EQ(pits, 75);
  EXPECT_EQ(tests, 100);
  std::cout << pits << " pits, " << tests << " saw tests read; " << without_density
            << " layers with no measured density and none a cited law gives\n";
}

TEST(ProfileReader, OnePitAsItsFileSays)
{
  // snowpits-18288, read by hand from the file: slope 35 deg; 9 layers (top, thickness [cm], form,
  // hardness): 0 6 DF F | 6 7 DF 4F | 13 11 RG 1F | 24 1 DF 1F- | 25 10 RG 1F- | 35 11 MFcr P |
  // 46 16 FC F | 62 17 MF K (top) 1F (bottom) | 79 3 MFpc 1F; density samples (13, 4, 220) and
  // (35, 4, 370); one PST on the layer at 54 cm: End, cut 50 of 100 cm.
  const SnowProfile p = read_profile((field_pits / "snowpilot" / "snowpits-18288-caaml.xml").string());
  EXPECT_EQ(p.slope_angle_deg.value_or(NAN), 35.0);
  const std::vector<double> tops = {0, 6, 13, 24, 25, 35, 46, 62, 79}, thicknesses = {6, 7, 11, 1, 10, 11, 16, 17, 3};
  const std::vector<std::string> forms = {"DF", "DF", "RG", "DF", "RG", "MFcr", "FC", "MF", "MFpc"},
                                 hardness = {"F", "4F", "1F", "1F-", "1F-", "P", "F", "K", "1F"};
  ASSERT_EQ(p.layers.size(), 9u);
  for (std::size_t k = 0; k < 9; ++k)
  {
    EXPECT_NEAR(p.layers[k].depth_top_m, tops[k] / 100, 1e-12);
    EXPECT_NEAR(p.layers[k].thickness_m, thicknesses[k] / 100, 1e-12);
    EXPECT_EQ(p.layers[k].grain_form, forms[k]);
    ASSERT_TRUE(p.layers[k].hardness);
    EXPECT_EQ(p.layers[k].hardness->text, hardness[k]);
  }
  ASSERT_TRUE(p.layers[7].hardness_bottom);
  EXPECT_EQ(p.layers[7].hardness_bottom->text, "1F");
  EXPECT_NEAR(p.height_m(), 0.82, 1e-12);
  ASSERT_EQ(p.density_samples.size(), 2u);
  EXPECT_EQ(p.density_samples[1].density_kg_m3, 370);
  ASSERT_EQ(p.saw_tests.size(), 1u);
  EXPECT_NEAR(p.saw_tests[0].failed_depth_m, 0.54, 1e-12);
  EXPECT_EQ(p.layer_at_depth(0.54), 6); // the FC layer 46-62 cm
  EXPECT_EQ(p.saw_tests[0].propagation, "End");
  // Layer 3 (13-24 cm) holds the sample at 13-17 cm: its density is measured, 220.
  const LayerProperties third = layer_properties(p, 2, modulus_laws().front(), 0.25);
  EXPECT_TRUE(third.density.measured);
  EXPECT_NEAR(third.density.value, 220, 1e-12);
  // Layer 7 (FC, F, no sample): Geldsetzer & Jamieson (2000) FC, 112 + 46 x 1 = 158.
  const LayerProperties seventh = layer_properties(p, 6, modulus_laws().front(), 0.25);
  EXPECT_FALSE(seventh.density.measured);
  EXPECT_NEAR(seventh.density.value, 158, 1e-12);
  EXPECT_NE(seventh.density.source.find("Geldsetzer & Jamieson (2000)"), std::string::npos);
  // Layer 8 (MF, K over 1F, no sample): melt forms are not among their classes: refused, named.
  try
  {
    layer_properties(p, 7, modulus_laws().front(), 0.25);
    ADD_FAILURE() << "an MF layer without a measured density got one";
  }
  catch (const ProfileError &e)
  {
    EXPECT_NE(std::string(e.what()).find("layer 8 (top at 62 cm)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("MF"), std::string::npos) << e.what();
  }
}

// snowpits-65798, by hand: its failed layer 8 (FC, 4F, 40-45 cm) lies between density samples
// (37-41 cm, 400) and (43-47 cm, 490), across the ice crust at 45 cm. As a slab layer its density is
// the overlap-weighted mean, (400 x 1 + 490 x 2) / 3 = 460; as a weak layer neither sample lies
// mostly in it (1 and 2 of their 4 cm), so Geldsetzer & Jamieson's FC at 4F gives it 112 + 46 x 2
// = 204. snowpits-19602: layer 4 (MFcr, 28-30 cm) only touches the sample at 30-34 cm, which
// measures none of it (it once counted by round-off): a melt form without a measurement is refused.
TEST(ProfileReader, WeakLayerDensityOnlyFromSamplesMostlyInIt)
{
  const SnowProfile p = read_profile((field_pits / "snowpilot" / "snowpits-65798-caaml.xml").string());
  ASSERT_NEAR(p.layers[7].depth_top_m, 0.40, 1e-12);
  ASSERT_NEAR(p.layers[7].thickness_m, 0.05, 1e-12);
  const LayerProperties slab = layer_properties(p, 7, modulus_laws().front(), 0.25);
  EXPECT_TRUE(slab.density.measured);
  EXPECT_NEAR(slab.density.value, 460, 1e-9);
  const Sourced weak = weak_layer_density(p, 7);
  EXPECT_FALSE(weak.measured);
  EXPECT_NEAR(weak.value, 204, 1e-12);
  EXPECT_NE(weak.source.find("mostly outside"), std::string::npos) << weak.source;
  // A layer that holds most of a sample keeps it: layer 3 (RG, 14-26 cm) holds 20-24 cm (370) and 1 cm
  // of 11-15 cm (330): 370 as a weak layer, (330 x 1 + 370 x 4) / 5 = 362 as a slab layer.
  EXPECT_NEAR(weak_layer_density(p, 2).value, 370, 1e-9);
  EXPECT_TRUE(weak_layer_density(p, 2).measured);
  EXPECT_NEAR(layer_properties(p, 2, modulus_laws().front(), 0.25).density.value, 362, 1e-9);
  const SnowProfile q = read_profile((field_pits / "snowpilot" / "snowpits-19602-caaml.xml").string());
  ASSERT_NEAR(q.layers[3].depth_top_m, 0.28, 1e-12);
  EXPECT_THROW(layer_properties(q, 3, modulus_laws().front(), 0.25), ProfileError);
  EXPECT_THROW(weak_layer_density(q, 3), ProfileError);
}

TEST(ProfileReader, CaamlRefusals)
{
  const std::string pit = "snowpits-18288-caaml.xml";
  const std::string ns = "http://caaml.org/Schemas/SnowProfileIACS/v6.0.3";
  expect_refused(edited(pit, ns, "http://caaml.org/Schemas/V5.0/Profiles/SnowProfileIACS", "v5.xml"),
                 {"not a CAAML v6.0 SnowProfile", "V5.0"});
  expect_refused(edited(pit, "<caaml:SnowProfile", "<caaml:AvalancheActivity", "other_root.xml"), {"AvalancheActivity"});
  {
    const std::string text = read(field_pits / "snowpilot" / pit);
    const fs::path torn = fs::temp_directory_path() / "anticrack_profile_torn.xml";
    std::ofstream(torn, std::ios::binary) << text.substr(0, text.size() / 2);
    expect_refused(torn, {"not well-formed XML", "line"});
  }
  expect_refused(edited(pit, "<caaml:depthTop uom=\"cm\">13", "<caaml:depthTop uom=\"mm\">130", "mm.xml"),
                 {"layer 3", "depthTop", "`mm`", "`cm`"});
  expect_refused(edited(pit, "<caaml:density uom=\"kgm-3\">220", "<caaml:density uom=\"gcm-3\">0.22", "gcm3.xml"),
                 {"density sample 1", "`gcm-3`", "`kgm-3`"});
  expect_refused(edited(pit, "<caaml:thickness uom=\"cm\">7", "<caaml:thickness uom=\"cm\">-7", "negative.xml"),
                 {"layer 2", "thickness", "positive"});
  expect_refused(edited(pit, "<caaml:thickness uom=\"cm\">7", "<caaml:thickness uom=\"cm\">9", "overlap.xml"),
                 {"layer 3", "overlaps"});
  expect_refused(edited(pit, "<caaml:thickness uom=\"cm\">7", "<caaml:thickness uom=\"cm\">NaN", "nan.xml"),
                 {"layer 2", "thickness", "`NaN` is not a finite number"});
  expect_refused(edited(pit, "<caaml:hardness uom=\"\">4F", "<caaml:hardness uom=\"\">4X", "hardness.xml"),
                 {"layer 2", "hardness `4X`", "F, 4F, 1F, P, K or I"});
  expect_refused(edited(pit, ">54<", ">120<", "failed_layer.xml"), {"propagation saw test 1", "120 cm", "not in the profile"});
  expect_refused(edited(pit, ">End<", ">Maybe<", "outcome.xml"), {"fracturePropagation `Maybe`", "End, Arr or SF"});
  expect_refused(edited(pit, "<caaml:density uom=\"kgm-3\">220", "<caaml:density uom=\"kgm-3\">0.22", "density_unit.xml"),
                 {"density sample 1", "0.22 kg/m^3", "another unit"});
  {
    // A 50 MB file is not parsed.
    const fs::path big = fs::temp_directory_path() / "anticrack_profile_big.xml";
    {
      std::ofstream out(big, std::ios::binary);
      out << read(field_pits / "snowpilot" / pit);
      const std::string comment = "<!--" + std::string(1 << 20, 'x') + "-->\n";
      for (int k = 0; k < 50; ++k)
        out << comment;
    }
    expect_refused(big, {"bytes, more than a snow profile"});
    fs::remove(big);
  }
}

TEST(ProfileReader, LayerTable)
{
  const fs::path file = fs::temp_directory_path() / "anticrack_profile_table.csv";
  std::ofstream(file) << "# a slab of two layers on a weak layer\n"
                         "thickness_cm,density_kg_m3,grain_form,grain_size_mm,hand_hardness,role\n"
                         "20,180,RG,0.5,4F,slab\n"
                         "15,,FC,1,1F,slab\n"
                         "2,,SH,4,F,weak\n"
                         "50,300,,,,base\n";
  const SnowProfile p = read_profile(file.string());
  EXPECT_EQ(p.format, "layer table");
  ASSERT_EQ(p.layers.size(), 4u);
  EXPECT_NEAR(p.layers[2].depth_top_m, 0.35, 1e-12);
  EXPECT_EQ(p.layers[2].role, LayerRole::weak);
  EXPECT_EQ(*p.layers[0].density_kg_m3, 180);
  EXPECT_FALSE(p.layers[1].density_kg_m3);
  // FC 1F: Geldsetzer & Jamieson (2000), 112 + 46 x 3 = 250.
  EXPECT_NEAR(layer_properties(p, 1, modulus_laws().front(), 0.25).density.value, 250, 1e-12);
  EXPECT_TRUE(layer_properties(p, 0, modulus_laws().front(), 0.25).density.measured);

  const auto table = [&](const std::string &name, const std::string &text) {
    const fs::path f = fs::temp_directory_path() / ("anticrack_profile_" + name + ".csv");
    std::ofstream(f) << text;
    return f;
  };
  const std::string header = "thickness_cm,density_kg_m3,grain_form,grain_size_mm,hand_hardness,role\n";
  expect_refused(table("mm", "thickness_mm,density_kg_m3\n200,180\n"), {"column `thickness_mm`", "`thickness_cm`"});
  expect_refused(table("gcm3", "thickness_cm,density_g_cm3\n20,0.18\n"), {"column `density_g_cm3`", "`density_kg_m3`"});
  expect_refused(table("unknown", "thickness_cm,colour\n20,red\n"), {"unknown column `colour`"});
  expect_refused(table("missing", header + "20,,RG,0.5,,slab\n"), {"layer 1 (line 2)", "neither density_kg_m3 nor both"});
  expect_refused(table("negative", header + "-20,180,RG,0.5,4F,slab\n"), {"layer 1", "must be positive"});
  expect_refused(table("nan", header + "20,nan,RG,0.5,4F,slab\n"), {"layer 1", "density_kg_m3 `nan`"});
  expect_refused(table("role", header + "20,180,RG,0.5,4F,roof\n"), {"role `roof`"});
  expect_refused(table("fields", header + "20,180,RG\n"), {"line 2", "3 fields"});
  expect_refused(table("grams", header + "20,0.18,RG,0.5,4F,slab\n"), {"0.18 kg/m^3", "another unit"});
  expect_refused(table("no_header", "# nothing\n"), {"no header line"});
}

TEST(LayerProperties, CitedLawsAtHandComputedPoints)
{
  // Geldsetzer & Jamieson (2000): rho = a + b h (RG: a + b h^c), h = F 1 ... I 6, +- 1/3.
  EXPECT_NEAR(*geldsetzer_jamieson_density("FC", 3), 112 + 46 * 3, 1e-12);          // 250
  EXPECT_NEAR(*geldsetzer_jamieson_density("DH", 4), 185 + 25 * 4, 1e-12);          // 285
  EXPECT_NEAR(*geldsetzer_jamieson_density("PP", 2), 45 + 36 * 2, 1e-12);           // 117
  EXPECT_NEAR(*geldsetzer_jamieson_density("RG", 3), 154 + 1.51 * 31.83699, 1e-4);  // 3^3.15 = 31.83699: 202.074
  EXPECT_NEAR(*geldsetzer_jamieson_density("FCxr", 3), 56 + 64 * 3, 1e-12);         // mixed facets, 248
  EXPECT_NEAR(*geldsetzer_jamieson_density("RGxf", 4), 91 + 42 * 4, 1e-12);         // mixed rounds, 259
  EXPECT_FALSE(geldsetzer_jamieson_density("MFcr", 4).has_value());
  EXPECT_FALSE(geldsetzer_jamieson_density("SH", 1).has_value());
  EXPECT_NEAR(parse_hand_hardness("1F-")->index, 3 - 1.0 / 3, 1e-12);
  EXPECT_NEAR(parse_hand_hardness(" K+ ")->index, 5 + 1.0 / 3, 1e-12);
  EXPECT_FALSE(parse_hand_hardness("4F-1F").has_value());
  // E at 250 kg/m^3, by hand from docs/physics.md §3: Gerling et al. (2017) 6.0e-10 x 250^4.6 =
  // 64.37 MPa; Scapozza (2004) 0.1873 exp(3.725) = 7.763 MPa (the 7.8 MPa of scenes/pst_flat.prm's
  // slab); Bergfeld et al. (2023) 6.5e3 (250/916.7)^4.4 = 21.38 MPa.
  EXPECT_NEAR(modulus_law("Gerling 2017").modulus(250) / 64.37e6, 1, 1e-3);
  EXPECT_NEAR(modulus_law("Scapozza 2004").modulus(250) / 7.763e6, 1, 1e-3);
  EXPECT_NEAR(modulus_law("Bergfeld 2023").modulus(250) / 21.38e6, 1, 1e-3);
  EXPECT_THROW(modulus_law("Hooke 1678"), std::out_of_range);
  // Sigrist (2006): 240 kPa (250/917)^2.44 = 10.07 kPa.
  EXPECT_NEAR(sigrist_tensile_strength(250) / 10.07e3, 1, 1e-3);
}
