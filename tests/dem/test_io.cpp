// Tests of the DEM I/O module (dem/io/state_hdf5.h, dem/io/state_vtp.h):
//   - a checkpoint written mid-run and read into a fresh system continues the run bit for bit
//     (periodic box, bonds, walls, a clump with an applied force, neighbour rebuilds after the
//     restart), and the loaded state equals the written one field by field;
//   - read_checkpoint rejects snapshots, wrong array sizes and unknown materials with a message
//     naming the dataset, and leaves the target system untouched;
//   - a snapshot read back with the plain HDF5 C API has the documented layout, sizes and values,
//     also with no bonds and no walls;
//   - VTP files are well-formed XML with the right point, vertex and line counts (periodic bonds
//     get an extra point), and the PVD collection lists its datasets and survives a restart.
#include "dem_test_helpers.h"

#include "dem/io/state_hdf5.h"
#include "dem/io/state_vtp.h"
#include "dem/sample/lattice.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <unistd.h>

namespace anticrack::dem
{
  namespace
  {
    namespace fs = std::filesystem;

    constexpr double density = 2650;
    constexpr double radius = 1e-3;

    Material io_material()
    {
      Material m;
      m.density = density;
      m.contact.contact_modulus = 1e9;
      m.contact.friction = 0.4;
      m.contact.damping_ratio = 0.05;
      m.bond.enabled = true;
      m.bond.modulus = 1e9;
      m.bond.tensile_strength = 2e6; // some bonds break during the run
      m.bond.cohesion = 4e6;
      m.bond.friction_angle = 0.5;
      return m;
    }

    /// A 4 x 4 x 3 bonded lattice in a box periodic along x and y (so some bonds cross the
    /// boundary), shaken by random velocities, on a floor wall, with a two-sphere clump falling on
    /// it under a ramped force and a piston wall moving down. Initialised.
    void build_scene(DemSystem &s)
    {
      s.materials.add(io_material());
      s.domain.lower = Vec3::Zero();
      s.domain.upper = Vec3(8e-3, 8e-3, 20e-3);
      s.domain.periodic = {true, true, false};
      LatticeSpec lattice;
      lattice.cells = {4, 4, 3};
      lattice.radius = radius;
      lattice.spacing = 2 * radius;
      lattice.velocity_amplitude = 0.5;
      lattice.seed = 7;
      add_simple_cubic_lattice(s, lattice);
      s.bond_touching_pairs(BondingRule{1e-6});

      const Index a = s.particles.add_sphere(Vec3(4e-3, 4e-3, 7.5e-3), radius, density);
      const Index b = s.particles.add_sphere(Vec3(4.6e-3, 4.2e-3, 8.8e-3), 0.8 * radius, density, 0, 3);
      Clump &clump = s.clumps[s.add_clump({a, b})];
      clump.velocity = Vec3(0.2, 0, -1.5);
      clump.angular_momentum = Vec3(1e-9, 0, 0);
      clump.applied_force = ForceHistory::ramp(2.0, Vec3(0, 0, -1));

      ContactParameters hertz;
      hertz.law = ContactLaw::hertz_mindlin;
      s.walls = {test::floor_wall(), test::make_wall("piston", -Vec3::UnitZ(), Vec3(0, 0, 18e-3), hertz,
                                                     WallControl::velocity, Vec3(0, 0, -0.5))};

      s.settings.gravity = Vec3(0, 0, -9.81);
      s.settings.local_damping = 0.05;
      s.initialise();
    }

    template <class T>
    bool bitwise_equal(const std::vector<T> &a, const std::vector<T> &b)
    {
      return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
    }

    std::string read_text(const std::string &file)
    {
      std::ifstream in(file);
      std::stringstream text;
      text << in.rdbuf();
      return text.str();
    }

    // --- minimal HDF5 readers for the snapshot test (plain C API, independent of io_hdf5.cpp)

    std::vector<hsize_t> dataset_shape(hid_t file, const char *path)
    {
      const hid_t set = H5Dopen2(file, path, H5P_DEFAULT);
      EXPECT_GE(set, 0) << path;
      const hid_t space = H5Dget_space(set);
      std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(space));
      H5Sget_simple_extent_dims(space, dims.data(), nullptr);
      H5Sclose(space);
      H5Dclose(set);
      return dims;
    }

    template <class T>
    std::vector<T> read_dataset(hid_t file, const char *path, hid_t type, std::size_t count)
    {
      std::vector<T> values(count);
      const hid_t set = H5Dopen2(file, path, H5P_DEFAULT);
      if (count > 0)
      {
        EXPECT_GE(H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << path;
      }
      H5Dclose(set);
      return values;
    }

    template <class T>
    T read_attribute(hid_t object, const char *name, hid_t type)
    {
      T value{};
      const hid_t attribute = H5Aopen(object, name, H5P_DEFAULT);
      EXPECT_GE(H5Aread(attribute, type, &value), 0) << name;
      H5Aclose(attribute);
      return value;
    }

    /// Memory type of the snapshot's strings: variable length, UTF-8 (HDF5 does not convert
    /// between ASCII and UTF-8, so a reader must ask for UTF-8).
    hid_t utf8_string_type()
    {
      const hid_t type = H5Tcopy(H5T_C_S1);
      H5Tset_size(type, H5T_VARIABLE);
      H5Tset_cset(type, H5T_CSET_UTF8);
      return type;
    }

    std::string read_string_attribute(hid_t object, const char *name)
    {
      const hid_t type = utf8_string_type();
      char *text = nullptr;
      const hid_t attribute = H5Aopen(object, name, H5P_DEFAULT);
      EXPECT_GE(H5Aread(attribute, type, &text), 0) << name;
      std::string value = text ? text : "";
      H5free_memory(text);
      H5Aclose(attribute);
      H5Tclose(type);
      return value;
    }

    std::string dataset_units(hid_t file, const char *path)
    {
      const hid_t set = H5Dopen2(file, path, H5P_DEFAULT);
      std::string units = read_string_attribute(set, "units");
      H5Dclose(set);
      return units;
    }

    // --- minimal XML checks for the VTP tests

    /// True when every start tag has its matching end tag (self-closing tags, the declaration and
    /// text content are allowed); `error` says what is wrong otherwise.
    bool well_formed_xml(const std::string &text, std::string &error)
    {
      std::vector<std::string> open;
      for (std::size_t at = text.find('<'); at != std::string::npos; at = text.find('<', at + 1))
      {
        const std::size_t end = text.find('>', at);
        if (end == std::string::npos)
          return error = "unterminated tag", false;
        const std::string tag = text.substr(at + 1, end - at - 1);
        if (tag.empty() || tag[0] == '?')
          continue;
        if (tag[0] == '/')
        {
          if (open.empty() || open.back() != tag.substr(1))
            return error = "unexpected </" + tag.substr(1) + ">", false;
          open.pop_back();
        }
        else if (tag.back() != '/')
          open.push_back(tag.substr(0, tag.find(' ')));
      }
      if (!open.empty())
        return error = "unclosed <" + open.back() + ">", false;
      return true;
    }

    long attribute_count(const std::string &text, const std::string &name)
    {
      std::smatch match;
      if (!std::regex_search(text, match, std::regex(name + "=\"([0-9]+)\"")))
        return -1;
      return std::stol(match[1]);
    }

    /// Number of whitespace-separated values inside the DataArray named `name`.
    long data_array_values(const std::string &text, const std::string &name)
    {
      const std::size_t begin = text.find(">", text.find("Name=\"" + name + "\""));
      const std::size_t end = text.find("</DataArray>", begin);
      std::istringstream values(text.substr(begin + 1, end - begin - 1));
      long count = 0;
      for (std::string value; values >> value;)
        ++count;
      return count;
    }
    /// Each test writes into its own directory, removed afterwards.
    class Io : public ::testing::Test
    {
    protected:
      void SetUp() override
      {
        const auto *test = ::testing::UnitTest::GetInstance()->current_test_info();
        directory_ = fs::temp_directory_path() /
                     ("anticrack_test_io_" + std::to_string(::getpid()) + "_" + test->name());
        fs::create_directories(directory_);
      }
      void TearDown() override { fs::remove_all(directory_); }
      [[nodiscard]] std::string temporary_path(const std::string &name) const
      {
        return (directory_ / name).string();
      }

    private:
      fs::path directory_;
    };
  } // namespace

  TEST_F(Io, CheckpointRoundTripContinuesBitForBit)
  {
    DemSystem original;
    build_scene(original);
    original.run(150);
    // A checkpoint at an arbitrary step (no rebuild first): the run must continue bit for bit.
    const std::string file = temporary_path("round_trip.h5");
    io::write_checkpoint(file, original);
    EXPECT_FALSE(fs::exists(file + ".tmp"));

    DemSystem restarted;
    restarted.materials.add(io_material());
    io::read_checkpoint(file, restarted);

    // The loaded state equals the written one.
    EXPECT_TRUE(bitwise_equal(restarted.particles.position, original.particles.position));
    EXPECT_TRUE(bitwise_equal(restarted.particles.inertia, original.particles.inertia));
    EXPECT_TRUE(bitwise_equal(restarted.particles.clump_id, original.particles.clump_id));
    EXPECT_TRUE(bitwise_equal(restarted.previous_velocity, original.previous_velocity));
    EXPECT_TRUE(bitwise_equal(restarted.contacts.shear_force, original.contacts.shear_force));
    EXPECT_TRUE(bitwise_equal(restarted.contacts.active, original.contacts.active));
    EXPECT_TRUE(bitwise_equal(restarted.contacts.overlap, original.contacts.overlap));
    EXPECT_EQ(restarted.contacts.load.size(), original.contacts.load.size());
    EXPECT_TRUE(bitwise_equal(restarted.bonds.state, original.bonds.state));
    EXPECT_TRUE(bitwise_equal(restarted.bonds.bending_moment, original.bonds.bending_moment));
    EXPECT_TRUE(bitwise_equal(restarted.bonds.tan_friction, original.bonds.tan_friction));
    EXPECT_TRUE(bitwise_equal(restarted.wall_shear, original.wall_shear));
    ASSERT_EQ(restarted.clumps.size(), 1u);
    const Clump &c0 = original.clumps[0], &c1 = restarted.clumps[0];
    EXPECT_EQ(c1.members, c0.members);
    EXPECT_TRUE(bitwise_equal(c1.member_offset, c0.member_offset));
    EXPECT_TRUE(c1.orientation.coeffs() == c0.orientation.coeffs());
    EXPECT_TRUE(c1.principal_frame.coeffs() == c0.principal_frame.coeffs());
    EXPECT_TRUE(c1.angular_momentum == c0.angular_momentum);
    EXPECT_EQ(c1.applied_force.time, c0.applied_force.time);
    EXPECT_TRUE(bitwise_equal(c1.applied_force.value, c0.applied_force.value));
    EXPECT_TRUE(c1.applied_force.extrapolate_linearly);
    ASSERT_EQ(restarted.walls.size(), 2u);
    EXPECT_EQ(restarted.walls[1].name, "piston");
    EXPECT_EQ(restarted.walls[1].control, WallControl::velocity);
    EXPECT_EQ(restarted.walls[1].contact.law, ContactLaw::hertz_mindlin);
    EXPECT_TRUE(restarted.walls[1].point == original.walls[1].point);
    EXPECT_EQ(restarted.domain.periodic, original.domain.periodic);
    EXPECT_TRUE(restarted.settings.gravity == original.settings.gravity);
    EXPECT_EQ(restarted.settings.local_damping, original.settings.local_damping);
    EXPECT_EQ(restarted.settings.enforce_critical_step, original.settings.enforce_critical_step);
    EXPECT_EQ(restarted.ledger.friction, original.ledger.friction);
    EXPECT_EQ(restarted.ledger.gravity_potential, original.ledger.gravity_potential);
    EXPECT_EQ(restarted.initial_balance, original.initial_balance);
    EXPECT_EQ(restarted.step_count, original.step_count);
    EXPECT_EQ(restarted.time, original.time);
    EXPECT_EQ(restarted.dt, original.dt);

    // Both continue identically, through neighbour rebuilds and time-step updates.
    restarted.resume();
    const Index builds_before = original.neighbor_builds();
    constexpr Index more_steps = 400;
    original.run(more_steps);
    restarted.run(more_steps);
    EXPECT_GT(original.neighbor_builds(), builds_before) << "the scenario should rebuild after the restart";
    EXPECT_TRUE(bitwise_equal(restarted.particles.position, original.particles.position));
    EXPECT_TRUE(bitwise_equal(restarted.particles.velocity, original.particles.velocity));
    EXPECT_TRUE(bitwise_equal(restarted.particles.angular_velocity, original.particles.angular_velocity));
    EXPECT_TRUE(bitwise_equal(restarted.bonds.shear_force, original.bonds.shear_force));
    EXPECT_TRUE(bitwise_equal(restarted.bonds.state, original.bonds.state));
    EXPECT_TRUE(restarted.clumps[0].orientation.coeffs() == original.clumps[0].orientation.coeffs());
    EXPECT_TRUE(restarted.walls[1].point == original.walls[1].point);
    EXPECT_EQ(restarted.time, original.time);
    EXPECT_EQ(restarted.dt, original.dt);
  }

  TEST_F(Io, CheckpointReaderRejectsBadFilesAndKeepsTheSystem)
  {
    DemSystem source;
    build_scene(source);
    const std::string snapshot = temporary_path("not_a_checkpoint.h5");
    const std::string checkpoint = temporary_path("damaged.h5");
    io::write_snapshot(snapshot, source);
    io::write_checkpoint(checkpoint, source);

    DemSystem target;
    target.materials.add(io_material());
    target.particles.add_sphere(Vec3::Zero(), radius, density);
    const auto expect_failure = [&](const std::string &file, const std::string &fragment) {
      try
      {
        io::read_checkpoint(file, target);
        ADD_FAILURE() << "read_checkpoint accepted " << file;
      }
      catch (const std::runtime_error &e)
      {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      }
      EXPECT_EQ(target.particles.size(), 1) << "a failed read must leave the system as it was";
    };
    expect_failure(snapshot, "format");
    expect_failure(temporary_path("missing.h5"), "open file");

    // A radius array one entry short.
    const hid_t file = H5Fopen(checkpoint.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "/particles/radius", H5P_DEFAULT), 0);
    const hsize_t short_size = source.particles.size() - 1;
    const hid_t space = H5Screate_simple(1, &short_size, nullptr);
    const hid_t set = H5Dcreate2(file, "/particles/radius", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT,
                                 H5P_DEFAULT);
    ASSERT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, source.particles.radius.data()),
              0);
    H5Dclose(set);
    H5Sclose(space);
    H5Fclose(file);
    expect_failure(checkpoint, "/particles/radius");

    // Materials come from the scene: a system without them cannot take the checkpoint.
    io::write_checkpoint(checkpoint, source);
    target.materials = MaterialTable{};
    expect_failure(checkpoint, "material_id");
  }

  TEST_F(Io, SnapshotLayoutReadWithTheCApi)
  {
    DemSystem s;
    build_scene(s);
    s.run(50);
    const std::string name = temporary_path("snapshot.h5");
    io::write_snapshot(name, s);

    const hid_t file = H5Fopen(name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_EQ(read_string_attribute(file, "format"), "anticrack-dem-snapshot");
    EXPECT_EQ(read_attribute<int>(file, "version", H5T_NATIVE_INT), 1);
    EXPECT_EQ(read_attribute<Index>(file, "step", H5T_NATIVE_INT64), s.step_count);
    EXPECT_EQ(read_attribute<double>(file, "time", H5T_NATIVE_DOUBLE), s.time);
    EXPECT_EQ(read_attribute<double>(file, "dt", H5T_NATIVE_DOUBLE), s.dt);

    const auto n = static_cast<hsize_t>(s.particles.size());
    const auto m = static_cast<hsize_t>(s.bonds.size());
    ASSERT_GT(m, 0u);
    EXPECT_EQ(dataset_shape(file, "/particles/position"), (std::vector<hsize_t>{n, 3}));
    EXPECT_EQ(dataset_shape(file, "/particles/radius"), (std::vector<hsize_t>{n}));
    EXPECT_EQ(dataset_shape(file, "/bonds/bending_moment"), (std::vector<hsize_t>{m, 3}));
    EXPECT_EQ(dataset_shape(file, "/walls/point"), (std::vector<hsize_t>{2, 3}));
    EXPECT_EQ(dataset_shape(file, "/domain/periodic"), (std::vector<hsize_t>{3}));

    const auto position = read_dataset<double>(file, "/particles/position", H5T_NATIVE_DOUBLE, 3 * n);
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(position[3 * 5 + a], s.particles.position[5][a]);
    EXPECT_EQ(read_dataset<int>(file, "/particles/clump_id", H5T_NATIVE_INT, n).back(), 0);
    const auto bond_j = read_dataset<Index>(file, "/bonds/j", H5T_NATIVE_INT64, m);
    const auto sigma = read_dataset<double>(file, "/bonds/sigma", H5T_NATIVE_DOUBLE, m);
    const auto tau = read_dataset<double>(file, "/bonds/tau", H5T_NATIVE_DOUBLE, m);
    const auto state = read_dataset<std::uint8_t>(file, "/bonds/state", H5T_NATIVE_UINT8, m);
    for (hsize_t b = 0; b < m; b += 7)
    {
      EXPECT_EQ(bond_j[b], s.bonds.j[b]);
      EXPECT_EQ(sigma[b], s.bonds.rim_stresses(b).first);
      EXPECT_EQ(tau[b], s.bonds.rim_stresses(b).second);
      EXPECT_EQ(state[b], static_cast<std::uint8_t>(s.bonds.state[b]));
    }
    EXPECT_EQ(read_dataset<int>(file, "/domain/periodic", H5T_NATIVE_INT, 3), (std::vector<int>{1, 1, 0}));
    EXPECT_EQ(dataset_units(file, "/particles/velocity"), "m/s");
    EXPECT_EQ(dataset_units(file, "/bonds/normal_force"), "N");

    // Wall names as variable-length strings.
    const hid_t string_type = utf8_string_type();
    auto names = read_dataset<char *>(file, "/walls/name", string_type, 2);
    EXPECT_STREQ(names[0], "floor");
    EXPECT_STREQ(names[1], "piston");
    for (char *text : names)
      H5free_memory(text);
    H5Tclose(string_type);

    const hid_t energy = H5Gopen2(file, "/energy", H5P_DEFAULT);
    EXPECT_EQ(read_attribute<double>(energy, "kinetic", H5T_NATIVE_DOUBLE), s.energy().kinetic);
    EXPECT_EQ(read_attribute<double>(energy, "external_work", H5T_NATIVE_DOUBLE), s.ledger.external_work);
    H5Gclose(energy);
    H5Fclose(file);
  }

  TEST_F(Io, SnapshotAndCheckpointWithoutBondsAndWalls)
  {
    DemSystem s;
    s.materials.add(Material{});
    s.domain.upper = Vec3::Constant(0.1);
    s.particles.add_sphere(Vec3::Constant(0.05), 1e-3, 1e3);
    s.initialise();
    const std::string snapshot = temporary_path("empty_snapshot.h5");
    const std::string checkpoint = temporary_path("empty_checkpoint.h5");
    io::write_snapshot(snapshot, s);
    io::write_checkpoint(checkpoint, s);

    const hid_t file = H5Fopen(snapshot.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_EQ(dataset_shape(file, "/bonds/i"), (std::vector<hsize_t>{0}));
    EXPECT_EQ(dataset_shape(file, "/bonds/shear_force"), (std::vector<hsize_t>{0, 3}));
    EXPECT_EQ(dataset_shape(file, "/walls/point"), (std::vector<hsize_t>{0, 3}));
    EXPECT_EQ(dataset_shape(file, "/walls/name"), (std::vector<hsize_t>{0}));
    H5Fclose(file);

    DemSystem restarted;
    restarted.materials.add(Material{});
    io::read_checkpoint(checkpoint, restarted);
    EXPECT_EQ(restarted.particles.size(), 1);
    EXPECT_EQ(restarted.bonds.size(), 0);
    EXPECT_TRUE(restarted.walls.empty());
    EXPECT_TRUE(restarted.clumps.empty());
  }

  TEST_F(Io, VtpFilesAreWellFormedWithTheRightCounts)
  {
    DemSystem s;
    build_scene(s);
    const std::string particles = temporary_path("particles.vtp");
    const std::string bonds = temporary_path("bonds.vtp");
    io::write_particles_vtp(particles, s);
    io::write_bonds_vtp(bonds, s);

    const long n = s.particles.size();
    const std::string particle_text = read_text(particles);
    std::string error;
    EXPECT_TRUE(well_formed_xml(particle_text, error)) << error;
    EXPECT_EQ(attribute_count(particle_text, "NumberOfPoints"), n);
    EXPECT_EQ(attribute_count(particle_text, "NumberOfVerts"), n);
    EXPECT_EQ(data_array_values(particle_text, "position"), 3 * n);
    EXPECT_EQ(data_array_values(particle_text, "radius"), n);
    EXPECT_EQ(data_array_values(particle_text, "angular_velocity"), 3 * n);
    EXPECT_EQ(data_array_values(particle_text, "clump_id"), n);

    long periodic_bonds = 0;
    for (const Vec3 &shift : s.bonds.shift)
      periodic_bonds += shift != Vec3::Zero();
    EXPECT_GT(periodic_bonds, 0) << "the scene should have bonds across the periodic boundary";
    const long m = s.bonds.size();
    const std::string bond_text = read_text(bonds);
    EXPECT_TRUE(well_formed_xml(bond_text, error)) << error;
    EXPECT_EQ(attribute_count(bond_text, "NumberOfPoints"), n + periodic_bonds);
    EXPECT_EQ(attribute_count(bond_text, "NumberOfLines"), m);
    EXPECT_EQ(data_array_values(bond_text, "position"), 3 * (n + periodic_bonds));
    EXPECT_EQ(data_array_values(bond_text, "connectivity"), 2 * m);
    EXPECT_EQ(data_array_values(bond_text, "sigma"), m);

    // No line is longer than a bond (periodic ones end at the image of j).
    const auto array_text = [&](const std::string &name) {
      return bond_text.substr(bond_text.find('>', bond_text.find("Name=\"" + name + "\"")) + 1);
    };
    std::istringstream positions(array_text("position"));
    std::vector<Vec3> points(n + periodic_bonds);
    for (Vec3 &x : points)
      positions >> x[0] >> x[1] >> x[2];
    EXPECT_TRUE(points[0] == s.particles.position[0]) << "positions must round-trip exactly";
    std::istringstream connectivity(array_text("connectivity"));
    for (long b = 0; b < m; ++b)
    {
      Index from, to;
      connectivity >> from >> to;
      EXPECT_LT((points[to] - points[from]).norm(), 2.1 * radius) << "bond " << b;
    }
  }

  TEST_F(Io, PvdCollectionListsDatasetsAndSurvivesARestart)
  {
    const std::string pvd = temporary_path("series.pvd");
    {
      io::PvdCollection series(pvd);
      series.add(0.0, temporary_path("particles_0.vtp"));
      series.add(1.5e-4, temporary_path("particles_1.vtp"));
      series.add(3e-4, temporary_path("particles_2.vtp"));
    }
    const std::string text = read_text(pvd);
    std::string error;
    EXPECT_TRUE(well_formed_xml(text, error)) << error;
    EXPECT_NE(text.find("timestep=\"0.00015\""), std::string::npos) << text;
    EXPECT_NE(text.find("file=\"particles_1.vtp\""), std::string::npos) << text;

    io::PvdCollection resumed(pvd);
    resumed.load_existing(2e-4); // restart from a checkpoint at t = 2e-4 s
    ASSERT_EQ(resumed.entries().size(), 2u);
    EXPECT_EQ(resumed.entries()[1].time, 1.5e-4);
    EXPECT_EQ(resumed.entries()[1].file, "particles_1.vtp");
    resumed.add(2.5e-4, temporary_path("particles_3.vtp"));
    const std::string resumed_text = read_text(pvd);
    EXPECT_EQ(resumed_text.find("particles_2.vtp"), std::string::npos);
    EXPECT_NE(resumed_text.find("particles_3.vtp"), std::string::npos);
  }
} // namespace anticrack::dem
