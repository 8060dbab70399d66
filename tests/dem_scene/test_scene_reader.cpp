// Tests of the DEM scene reader (dem/scene/parameters): scene kinds and variants declare only
// their own entries, an entry of another kind or variant is refused with a message naming both,
// and the entries a variant does not declare keep values equal to the documented defaults (so
// that declaring per variant cannot change a result). Also the parameter-file scanner and the
// enum tables the reader is built on (util/parameter_files, util/enum_table).
#include "dem/scene/parameters.h"
#include "util/enum_table.h"
#include "util/input_error.h"
#include "util/parameter_files.h"

#include <deal.II/base/parameter_handler.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace
{
  using namespace anticrack;
  using dem::SceneKind;
  using dem::parameters::Loading;
  using dem::parameters::Sample;

  /// Writes `text` to a fresh file in the temporary directory and returns its path.
  std::string scene_file(const std::string &name, const std::string &text)
  {
    const auto path = std::filesystem::temp_directory_path() / ("anticrack_dem_scene_" + name + ".prm");
    std::ofstream(path) << text;
    return path.string();
  }

  /// The message of the InputError that reading `text` as a scene of `kind` throws ("" if none).
  std::string refusal(const std::string &name, const std::string &text, const SceneKind kind)
  {
    try
    {
      dem::read_scene(scene_file(name, text), kind);
    }
    catch (const InputError &e)
    {
      return e.what();
    }
    return "";
  }

  const std::string lattice_scene = "set Scene = dem\n"
                                    "subsection DEM\n"
                                    "  set Steps = 10\n"
                                    "  subsection Sample\n"
                                    "    set Type = simple cubic lattice\n"
                                    "    set Lattice size = 2, 2, 2\n"
                                    "  end\n"
                                    "end\n";
} // namespace

TEST(ParameterFileScan, SubsectionsCommentsContinuationsAndLines)
{
  const auto settings = scan_parameter_settings("# a comment\n"
                                                "set Scene = dem   # trailing comment\n"
                                                "subsection DEM\n"
                                                "  subsection Sample\n"
                                                "    set Radius [m] = 1e-3\n"
                                                "    set Lattice size = 2, \\\n"
                                                "                       3, 4\n"
                                                "  end\n"
                                                "  set Steps = 5\n"
                                                "end\n");
  ASSERT_EQ(settings.size(), 4u);
  EXPECT_EQ(settings[0].path_text(), "Scene");
  EXPECT_EQ(settings[0].value, "dem");
  EXPECT_EQ(settings[1].path_text(), "DEM/Sample/Radius [m]");
  EXPECT_EQ(settings[1].line, 5u);
  EXPECT_EQ(settings[2].path_text(), "DEM/Sample/Lattice size");
  EXPECT_EQ(settings[2].value, "2, 3, 4");
  EXPECT_EQ(settings[3].path_text(), "DEM/Steps");
  EXPECT_EQ(settings[3].line, 9u);
  EXPECT_TRUE(scan_parameter_settings("# only comments\n\n  # and blanks\n").empty());
}

TEST(EnumTable, PatternValueNameAndRefusal)
{
  enum class Colour
  {
    red,
    green
  };
  const EnumTable<Colour> table{{"red", Colour::red}, {"dark green", Colour::green}};
  EXPECT_EQ(table.pattern(), "red|dark green");
  EXPECT_EQ(table.value("dark green"), Colour::green);
  EXPECT_EQ(table.name(Colour::red), "red");
  // No fall-back to a default: a name the table lacks is an error.
  EXPECT_THROW(table.value("blue"), std::invalid_argument);
}

TEST(DemSceneReader, ReadsTheEntriesOfItsVariant)
{
  const dem::SceneParameters scene = dem::read_scene(scene_file("lattice", lattice_scene), SceneKind::dem);
  EXPECT_EQ(scene.kind, SceneKind::dem);
  EXPECT_STREQ(scene.dem.sample.type->name, "simple cubic lattice");
  EXPECT_EQ(scene.dem.sample.lattice_size, (std::array<dem::Index, 3>{2, 2, 2}));
  EXPECT_FALSE(scene.campaign.enabled());
}

TEST(DemSceneReader, RefusesAnEntryOfAnotherSampleType)
{
  std::string text = lattice_scene;
  text.insert(text.find("  end\nend"), "    set Volume fraction = 0.3\n");
  const std::string message = refusal("foreign_sample", text, SceneKind::dem);
  EXPECT_NE(message.find("DEM/Sample/Volume fraction"), std::string::npos) << message;
  EXPECT_NE(message.find("sticky hard spheres"), std::string::npos) << message;
  EXPECT_NE(message.find("simple cubic lattice"), std::string::npos) << message;
  EXPECT_NE(message.find("line 7"), std::string::npos) << message;
}

TEST(DemSceneReader, RefusesAnEntryOfAnotherTest)
{
  std::string text = lattice_scene;
  text.insert(text.find("end\n", text.find("  end\n") + 6),
              "  subsection Loading\n    set Test = triaxial\n    set Lag tolerance = 0.1\n  end\n");
  const std::string message = refusal("foreign_test", text, SceneKind::dem);
  EXPECT_NE(message.find("DEM/Loading/Lag tolerance"), std::string::npos) << message;
  EXPECT_NE(message.find("clump force"), std::string::npos) << message;
  EXPECT_NE(message.find("`triaxial`"), std::string::npos) << message;
}

TEST(DemSceneReader, CampaignBelongsToCampaignKinds)
{
  const std::string with_campaign = lattice_scene + "subsection Campaign\n  set Loading angles [deg] = 0, 90\nend\n";
  const std::string message = refusal("foreign_campaign", with_campaign, SceneKind::dem);
  EXPECT_NE(message.find("subsection Campaign belongs to scenes of kind campaign"), std::string::npos) << message;
  // A campaign scene needs its angles.
  std::string campaign = lattice_scene;
  campaign.replace(campaign.find("set Scene = dem"), 15, "set Scene = campaign");
  const std::string no_angles = refusal("campaign_without_angles", campaign, SceneKind::campaign);
  EXPECT_NE(no_angles.find("Campaign/Loading angles [deg]"), std::string::npos) << no_angles;
}

// Declaring only a variant's entries must not change a result: an entry that a scene of one
// variant does not declare keeps the struct's default, which must equal the default the entry
// documents (and that every earlier scene read when it did not set the entry).
TEST(DemSceneReader, UndeclaredEntriesKeepTheDocumentedDefaults)
{
  dealii::ParameterHandler every_variant;
  dem::declare_dem_scene(every_variant, dem::Declaration{});
  every_variant.enter_subsection("DEM");
  for (const dem::SampleType &type : dem::sample_types())
  {
    const std::string name = type.name;
    every_variant.enter_subsection("Sample");
    every_variant.set("Type", std::string(name));
    every_variant.leave_subsection();
    Sample from_defaults;
    from_defaults.parse_parameters(every_variant); // reads only the entries of `type`, at their defaults
    Sample built_in;
    built_in.type = &type;
    EXPECT_EQ(from_defaults.lattice_size, built_in.lattice_size) << name;
    EXPECT_EQ(from_defaults.radius, built_in.radius) << name;
    EXPECT_EQ(from_defaults.spacing, built_in.spacing) << name;
    EXPECT_EQ(from_defaults.origin, built_in.origin) << name;
    EXPECT_EQ(from_defaults.particle_count, built_in.particle_count) << name;
    EXPECT_EQ(from_defaults.volume_fraction, built_in.volume_fraction) << name;
    EXPECT_EQ(from_defaults.stickiness, built_in.stickiness) << name;
    EXPECT_EQ(from_defaults.target_coordination, built_in.target_coordination) << name;
    EXPECT_EQ(from_defaults.well_width, built_in.well_width) << name;
    EXPECT_EQ(from_defaults.sweeps, built_in.sweeps) << name;
    EXPECT_EQ(from_defaults.cluster_move_fraction, built_in.cluster_move_fraction) << name;
    EXPECT_EQ(from_defaults.box_edge, built_in.box_edge) << name;
    EXPECT_EQ(from_defaults.box_aspect_ratios, built_in.box_aspect_ratios) << name;
    EXPECT_EQ(from_defaults.rolling, built_in.rolling) << name;
    EXPECT_EQ(from_defaults.radius_half_width, built_in.radius_half_width) << name;
    EXPECT_EQ(from_defaults.formation_friction, built_in.formation_friction) << name;
    EXPECT_EQ(from_defaults.packing_pressure, built_in.packing_pressure) << name;
    EXPECT_EQ(from_defaults.disc_diameter, built_in.disc_diameter) << name;
  }
  for (const dem::LabTest &test : dem::lab_tests())
  {
    const std::string name = test.name;
    every_variant.enter_subsection("Loading");
    every_variant.set("Test", std::string(name));
    every_variant.leave_subsection();
    Loading from_defaults;
    from_defaults.parse_parameters(every_variant);
    Loading built_in;
    built_in.test = &test;
    EXPECT_EQ(from_defaults.adaptive, built_in.adaptive) << name;
    EXPECT_EQ(from_defaults.ramp.interval, built_in.ramp.interval) << name;
    EXPECT_EQ(from_defaults.ramp.recovery_factor, built_in.ramp.recovery_factor) << name;
    EXPECT_EQ(from_defaults.ramp.lag_tolerance, built_in.ramp.lag_tolerance) << name;
    EXPECT_EQ(from_defaults.stop_strain, built_in.stop_strain) << name;
    EXPECT_EQ(from_defaults.normal_stress, built_in.normal_stress) << name;
    EXPECT_EQ(from_defaults.shear_velocity, built_in.shear_velocity) << name;
    EXPECT_EQ(from_defaults.consolidation_time, built_in.consolidation_time) << name;
    EXPECT_EQ(from_defaults.final_shear_strain, built_in.final_shear_strain) << name;
    EXPECT_EQ(from_defaults.confining_pressure, built_in.confining_pressure) << name;
    EXPECT_EQ(from_defaults.axial_strain_rate, built_in.axial_strain_rate) << name;
    EXPECT_EQ(from_defaults.final_axial_strain, built_in.final_axial_strain) << name;
    EXPECT_EQ(from_defaults.max_servo_speed, built_in.max_servo_speed) << name;
    EXPECT_EQ(from_defaults.platen_speed, built_in.platen_speed) << name;
    EXPECT_EQ(from_defaults.post_peak_fraction, built_in.post_peak_fraction) << name;
  }
  every_variant.leave_subsection();
}
