// HDF5 snapshots and checkpoints of the DEM system (file layout documented in state_hdf5.h).
//
// Structure: the project's HDF5 layer (util/hdf5_file.h: handles, groups, attributes, table
// datasets, strings), one generic reader and writer per kind of thing (array dataset, attribute)
// that maps the C++ element types onto it, and field lists that name each array once and are used
// by both the writer and the reader, so the two cannot drift apart:
//   - structure-of-arrays stores (particles, contacts, bonds) list their std::vector members;
//   - arrays of structs (walls, clumps) list accessors; the writer gathers one column per field
//     (ragged std::vector fields are concatenated with a per-item count) and the reader scatters.
// Types HDF5 has no native form for are converted on the way: bool/char -> uint8, enums -> their
// underlying integer, Quat -> 4 doubles (w, x, y, z).
#include "dem/io/state_hdf5.h"

#include "util/atomic_file.h"
#include "util/hdf5_file.h"

#include <hdf5.h>

#include <array>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <utility>

namespace anticrack::dem::io
{
  namespace
  {
    constexpr const char *snapshot_format = "anticrack-dem-snapshot";
    constexpr const char *checkpoint_format = "anticrack-dem-checkpoint";
    constexpr int format_version = 1;
    constexpr Index any_rows = hdf5::any_rows;

    [[noreturn]] void fail(const std::string &where, const std::string &message)
    {
      throw std::runtime_error("anticrack::dem::io: " + where + ": " + message);
    }

    // ------------------------------------------------------------------------------------------
    // Element types: how a C++ element is stored

    template <class T>
    struct Layout ///< arithmetic types HDF5 knows natively: one column
    {
      using Scalar = T;
      static constexpr hsize_t columns = 1;
    };
    template <>
    struct Layout<Vec3>
    {
      using Scalar = double;
      static constexpr hsize_t columns = 3;
    };
    template <class S, std::size_t K>
    struct Layout<std::array<S, K>>
    {
      using Scalar = S;
      static constexpr hsize_t columns = K;
    };

    template <class T>
    constexpr bool is_native =
      std::is_same_v<T, double> || std::is_same_v<T, int> || std::is_same_v<T, std::int64_t> ||
      std::is_same_v<T, std::uint8_t> || std::is_same_v<T, Vec3> || std::is_same_v<T, std::array<double, 4>>;

    template <class T>
    constexpr bool is_vector = false;
    template <class T, class A>
    constexpr bool is_vector<std::vector<T, A>> = true;

    template <class Scalar>
    hid_t native_type()
    {
      if constexpr (std::is_same_v<Scalar, double>)
        return H5T_NATIVE_DOUBLE;
      else if constexpr (std::is_same_v<Scalar, int>)
        return H5T_NATIVE_INT;
      else if constexpr (std::is_same_v<Scalar, std::int64_t>)
        return H5T_NATIVE_INT64;
      else
      {
        static_assert(std::is_same_v<Scalar, std::uint8_t>, "no HDF5 type for this scalar");
        return H5T_NATIVE_UINT8;
      }
    }

    // Conversions of the element types HDF5 has no native form for (to the stored form and back).
    std::uint8_t to_stored(bool value) { return value ? 1 : 0; }
    std::uint8_t to_stored(char value) { return static_cast<std::uint8_t>(value); }
    template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
    std::underlying_type_t<E> to_stored(E value)
    {
      return static_cast<std::underlying_type_t<E>>(value);
    }
    std::array<double, 4> to_stored(const Quat &q) { return {q.w(), q.x(), q.y(), q.z()}; }

    void from_stored(std::uint8_t stored, bool &value) { value = stored != 0; }
    void from_stored(std::uint8_t stored, char &value) { value = static_cast<char>(stored); }
    template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
    void from_stored(std::underlying_type_t<E> stored, E &value)
    {
      value = static_cast<E>(stored);
    }
    void from_stored(const std::array<double, 4> &stored, Quat &q)
    {
      q = Quat(stored[0], stored[1], stored[2], stored[3]);
    }

    // ------------------------------------------------------------------------------------------
    // Attributes holding one element (scalar, or a small 1-D array for Vec3)

    template <class T>
    void write_attribute(const hdf5::Handle &object, const std::string &name, const T &value)
    {
      if constexpr (!is_native<T>)
        write_attribute(object, name, to_stored(value));
      else
      {
        using L = Layout<T>;
        const hid_t type = native_type<typename L::Scalar>();
        hdf5::write_attribute(object.id, name, type, type, &value, L::columns);
      }
    }

    template <class T>
    void read_attribute(const hdf5::Handle &object, const std::string &name, T &value)
    {
      if constexpr (!is_native<T>)
      {
        decltype(to_stored(value)) stored{};
        read_attribute(object, name, stored);
        from_stored(stored, value);
      }
      else
      {
        using L = Layout<T>;
        hdf5::read_attribute(object.id, name, native_type<typename L::Scalar>(), &value, L::columns);
      }
    }

    template <class T>
    T read_attribute(const hdf5::Handle &object, const std::string &name)
    {
      T value{};
      read_attribute(object, name, value);
      return value;
    }

    // ------------------------------------------------------------------------------------------
    // Array datasets: rows x columns (1-D when there is one column), any number of rows incl. 0,
    // each with its `units` attribute

    /// Writes one array: numbers (N), Vec3 (N x 3), 4-arrays (N x 4), strings, or any type with a
    /// to_stored conversion.
    template <class T>
    void write_array(const hdf5::Handle &group, const std::string &name, const std::vector<T> &values, const std::string &unit)
    {
      if constexpr (std::is_same_v<T, std::string>)
      {
        const hdf5::Handle set = hdf5::write_string_dataset(group.id, name, values);
        hdf5::write_string_attribute(set.id, "units", unit);
      }
      else if constexpr (!is_native<T>)
      {
        std::vector<decltype(to_stored(std::declval<T>()))> stored;
        stored.reserve(values.size());
        for (const auto &value : values) // (auto, not T: std::vector<bool> yields proxies)
          stored.push_back(to_stored(static_cast<T>(value)));
        write_array(group, name, stored, unit);
      }
      else
      {
        using L = Layout<T>;
        static_assert(sizeof(T) == L::columns * sizeof(typename L::Scalar), "element is not a packed array");
        const hid_t type = native_type<typename L::Scalar>();
        const std::vector<hsize_t> dims =
          L::columns == 1 ? std::vector<hsize_t>{values.size()} : std::vector<hsize_t>{values.size(), L::columns};
        const hdf5::Handle set = hdf5::write_dataset(group.id, name, type, type, dims, values.data());
        hdf5::write_string_attribute(set.id, "units", unit);
      }
    }

    /// Reads one array written by write_array; `rows` is the required length (or any_rows).
    template <class T>
    void read_array(const hdf5::Handle &group, const std::string &name, std::vector<T> &values, Index rows)
    {
      if constexpr (std::is_same_v<T, std::string>)
      {
        const auto [set, count] = hdf5::open_table(group.id, name, 1, rows);
        values = hdf5::read_strings(set.id, count, hdf5::location(group.id, name));
      }
      else if constexpr (!is_native<T>)
      {
        std::vector<decltype(to_stored(std::declval<T>()))> stored;
        read_array(group, name, stored, rows);
        values.resize(stored.size());
        for (std::size_t k = 0; k < stored.size(); ++k)
        {
          T value{};
          from_stored(stored[k], value);
          values[k] = value;
        }
      }
      else
      {
        using L = Layout<T>;
        const auto [set, count] = hdf5::open_table(group.id, name, L::columns, rows);
        values.resize(count);
        if (count > 0)
          hdf5::read_dataset(set.id, native_type<typename L::Scalar>(), values.data(), hdf5::location(group.id, name));
      }
    }

    // ------------------------------------------------------------------------------------------
    // Validation helpers for the reader

    Index read_count(const hdf5::Handle &group)
    {
      const auto count = read_attribute<Index>(group, "count");
      if (count < 0)
        fail(hdf5::location(group.id) + "@count", "negative count " + std::to_string(count));
      return count;
    }

    /// Every value of `values` must lie in [lower, upper); `rule` explains why, for the message.
    template <class T>
    void check_range(const hdf5::Handle &node, const std::string &name, const std::vector<T> &values, Index lower,
                     Index upper, const std::string &rule)
    {
      for (std::size_t k = 0; k < values.size(); ++k)
        if (values[k] < lower || values[k] >= upper)
          fail(hdf5::location(node.id, name), "entry " + std::to_string(k) + " is " + std::to_string(values[k]) +
                                   ", outside [" + std::to_string(lower) + ", " + std::to_string(upper) +
                                   "): " + rule);
    }

    /// Run-state arrays are empty before initialise() and `rows` long after it.
    template <class T>
    void check_empty_or_rows(const hdf5::Handle &node, const std::string &name, const std::vector<T> &values,
                             Index rows)
    {
      if (!values.empty() && static_cast<Index>(values.size()) != rows)
        fail(hdf5::location(node.id, name),
             "has " + std::to_string(values.size()) + " rows, expected 0 or " + std::to_string(rows));
    }

    // ------------------------------------------------------------------------------------------
    // Field lists. `Store` / `Ledger` / `Settings` are the plain or const type, so one list serves
    // the writer and the reader.

    template <class Store, class Visit>
    void particle_arrays(Store &p, Visit &&visit)
    {
      visit("position", p.position, "m");
      visit("velocity", p.velocity, "m/s");
      visit("angular_velocity", p.angular_velocity, "rad/s");
      visit("force", p.force, "N");
      visit("torque", p.torque, "N m");
      visit("radius", p.radius, "m");
      visit("mass", p.mass, "kg");
      visit("inertia", p.inertia, "kg m^2");
      visit("material_id", p.material_id, "-");
      visit("group_id", p.group_id, "-");
      visit("clump_id", p.clump_id, "-");
      visit("blocked", p.blocked, "-");
    }

    template <class Store, class Visit>
    void contact_arrays(Store &c, Visit &&visit)
    {
      visit("i", c.i, "-");
      visit("j", c.j, "-");
      visit("shift", c.shift, "m");
      visit("shear_force", c.shear_force, "N");
      visit("normal", c.normal, "-");
      visit("active", c.active, "-");
      visit("overlap", c.overlap, "m");
      visit("dashpot_force", c.dashpot_force, "N");
    }

    /// Bond arrays of the snapshot (state and geometry).
    template <class Store, class Visit>
    void bond_state_arrays(Store &b, Visit &&visit)
    {
      visit("i", b.i, "-");
      visit("j", b.j, "-");
      visit("shift", b.shift, "m");
      visit("state", b.state, "-");
      visit("radius", b.radius, "m");
      visit("normal_force", b.normal_force, "N");
      visit("shear_force", b.shear_force, "N");
      visit("twist_moment", b.twist_moment, "N m");
      visit("bending_moment", b.bending_moment, "N m");
    }

    /// Further bond arrays needed for a restart.
    template <class Store, class Visit>
    void bond_restart_arrays(Store &b, Visit &&visit)
    {
      visit("normal", b.normal, "-");
      visit("normal_stiffness", b.normal_stiffness, "N/m");
      visit("shear_stiffness", b.shear_stiffness, "N/m");
      visit("twist_stiffness", b.twist_stiffness, "N m/rad");
      visit("bending_stiffness", b.bending_stiffness, "N m/rad");
      visit("tensile_strength", b.tensile_strength, "Pa");
      visit("cohesion", b.cohesion, "Pa");
      visit("tan_friction", b.tan_friction, "-");
      visit("moment_factor", b.moment_factor, "-");
    }

    template <class Visit>
    void wall_fields(Visit &&visit)
    {
      visit("name", [](auto &w) -> auto & { return w.name; }, "-");
      visit("point", [](auto &w) -> auto & { return w.point; }, "m");
      visit("normal", [](auto &w) -> auto & { return w.normal; }, "-");
      visit("velocity", [](auto &w) -> auto & { return w.velocity; }, "m/s");
      visit("force", [](auto &w) -> auto & { return w.force; }, "N");
      visit("control", [](auto &w) -> auto & { return w.control; }, "0 fixed, 1 velocity, 2 servo");
      visit("target_stress", [](auto &w) -> auto & { return w.target_stress; }, "Pa");
      visit("area", [](auto &w) -> auto & { return w.area; }, "m^2");
      visit("servo_gain", [](auto &w) -> auto & { return w.servo_gain; }, "m/(s N)");
      visit("max_speed", [](auto &w) -> auto & { return w.max_speed; }, "m/s");
      visit("contact_law", [](auto &w) -> auto & { return w.contact.law; }, "0 linear, 1 hertz_mindlin");
      visit("contact_modulus", [](auto &w) -> auto & { return w.contact.contact_modulus; }, "Pa");
      visit("stiffness_ratio", [](auto &w) -> auto & { return w.contact.stiffness_ratio; }, "-");
      visit("friction", [](auto &w) -> auto & { return w.contact.friction; }, "-");
      visit("damping_ratio", [](auto &w) -> auto & { return w.contact.damping_ratio; }, "-");
      visit("young_modulus", [](auto &w) -> auto & { return w.contact.young_modulus; }, "Pa");
      visit("poisson_ratio", [](auto &w) -> auto & { return w.contact.poisson_ratio; }, "-");
    }

    template <class Visit>
    void clump_fields(Visit &&visit)
    {
      visit("members", [](auto &c) -> auto & { return c.members; }, "-");
      visit("member_offset", [](auto &c) -> auto & { return c.member_offset; }, "m");
      visit("mass", [](auto &c) -> auto & { return c.mass; }, "kg");
      visit("centre", [](auto &c) -> auto & { return c.centre; }, "m");
      visit("displacement", [](auto &c) -> auto & { return c.displacement; }, "m");
      visit("velocity", [](auto &c) -> auto & { return c.velocity; }, "m/s");
      visit("angular_momentum", [](auto &c) -> auto & { return c.angular_momentum; }, "kg m^2/s");
      visit("angular_velocity", [](auto &c) -> auto & { return c.angular_velocity; }, "rad/s");
      visit("orientation", [](auto &c) -> auto & { return c.orientation; }, "quaternion w, x, y, z");
      visit("principal_inertia", [](auto &c) -> auto & { return c.principal_inertia; }, "kg m^2");
      visit("principal_frame", [](auto &c) -> auto & { return c.principal_frame; }, "quaternion w, x, y, z");
      visit("rotation_locked", [](auto &c) -> auto & { return c.rotation_locked; }, "-");
      visit("blocked", [](auto &c) -> auto & { return c.blocked; }, "-");
      visit("held_axes", [](auto &c) -> auto & { return c.held_axes; }, "-");
      visit("applied_force_time", [](auto &c) -> auto & { return c.applied_force.time; }, "s");
      visit("applied_force_value", [](auto &c) -> auto & { return c.applied_force.value; }, "N");
      visit("applied_force_extrapolate",
            [](auto &c) -> auto & { return c.applied_force.extrapolate_linearly; }, "-");
      visit("force", [](auto &c) -> auto & { return c.force; }, "N");
      visit("torque", [](auto &c) -> auto & { return c.torque; }, "N m");
    }

    template <class Settings, class Visit>
    void settings_fields(Settings &s, Visit &&visit)
    {
      visit("gravity", s.gravity);
      visit("local_damping", s.local_damping);
      visit("time_step", s.time_step);
      visit("time_step_safety", s.time_step_safety);
      visit("enforce_critical_step", s.enforce_critical_step);
      visit("time_step_interval", s.time_step_interval);
      visit("verlet_skin", s.verlet_skin);
      visit("stability_check_interval", s.stability_check_interval);
      visit("energy_drift_tolerance", s.energy_drift_tolerance);
    }

    template <class Ledger, class Visit>
    void energy_fields(Ledger &e, Visit &&visit)
    {
      visit("kinetic", e.kinetic);
      visit("elastic_contacts", e.elastic_contacts);
      visit("elastic_bonds", e.elastic_bonds);
      visit("gravity_potential", e.gravity_potential);
      visit("friction", e.friction);
      visit("viscous", e.viscous);
      visit("local_damping", e.local_damping);
      visit("bond_breakage", e.bond_breakage);
      visit("external_work", e.external_work);
    }

    // ------------------------------------------------------------------------------------------
    // Group writers and readers built on the field lists

    /// Creates group `name` with its `count` attribute.
    hdf5::Handle create_array_group(const hdf5::Handle &parent, const std::string &name, Index count)
    {
      hdf5::Handle group = hdf5::create_group(parent.id, name);
      write_attribute(group, "count", count);
      return group;
    }

    auto array_writer(const hdf5::Handle &group)
    {
      return [&group](const char *name, const auto &values, const char *unit) {
        write_array(group, name, values, unit);
      };
    }
    auto array_reader(const hdf5::Handle &group, Index rows)
    {
      return [&group, rows](const char *name, auto &values, const char *) {
        read_array(group, name, values, rows);
      };
    }

    /// Writes an array of structs one column per field; ragged vector fields are concatenated and
    /// accompanied by `<name>_count`.
    template <class Struct, class Fields>
    void write_table(const hdf5::Handle &parent, const std::string &name, const std::vector<Struct> &items,
                     Fields fields)
    {
      const hdf5::Handle group = create_array_group(parent, name, static_cast<Index>(items.size()));
      fields([&](const char *field, auto access, const char *unit) {
        using T = std::decay_t<decltype(access(std::declval<const Struct &>()))>;
        if constexpr (is_vector<T>)
        {
          std::vector<Index> counts;
          T concatenated;
          for (const Struct &item : items)
          {
            counts.push_back(static_cast<Index>(access(item).size()));
            concatenated.insert(concatenated.end(), access(item).begin(), access(item).end());
          }
          write_array(group, field, concatenated, unit);
          write_array(group, std::string(field) + "_count", counts, "-");
        }
        else
        {
          std::vector<T> column;
          for (const Struct &item : items)
            column.push_back(access(item));
          write_array(group, field, column, unit);
        }
      });
    }

    /// Reads what write_table wrote into `items` (resized to the stored count).
    template <class Struct, class Fields>
    void read_table(const hdf5::Handle &parent, const std::string &name, std::vector<Struct> &items, Fields fields)
    {
      const hdf5::Handle group = hdf5::open_group(parent.id, name);
      items.assign(read_count(group), Struct{});
      fields([&](const char *field, auto access, const char *) {
        using T = std::decay_t<decltype(access(std::declval<Struct &>()))>;
        if constexpr (is_vector<T>)
        {
          const std::string count_name = std::string(field) + "_count";
          std::vector<Index> counts;
          read_array(group, count_name, counts, static_cast<Index>(items.size()));
          Index total = 0;
          for (Index count : counts)
          {
            if (count < 0)
              fail(hdf5::location(group.id, count_name), "negative count " + std::to_string(count));
            total += count;
          }
          T concatenated;
          read_array(group, field, concatenated, total);
          Index first = 0;
          for (std::size_t k = 0; k < items.size(); ++k)
          {
            access(items[k]).assign(concatenated.begin() + first, concatenated.begin() + first + counts[k]);
            first += counts[k];
          }
        }
        else
        {
          std::vector<T> column;
          read_array(group, field, column, static_cast<Index>(items.size()));
          for (std::size_t k = 0; k < items.size(); ++k)
            access(items[k]) = column[k];
        }
      });
    }

    void write_domain(const hdf5::Handle &root, const Domain &domain)
    {
      const hdf5::Handle group = hdf5::create_group(root.id, "domain");
      write_array(group, "lower", std::vector<double>(domain.lower.begin(), domain.lower.end()), "m");
      write_array(group, "upper", std::vector<double>(domain.upper.begin(), domain.upper.end()), "m");
      write_array(group, "periodic", std::vector<int>(domain.periodic.begin(), domain.periodic.end()), "-");
    }

    Domain read_domain(const hdf5::Handle &root)
    {
      const hdf5::Handle group = hdf5::open_group(root.id, "domain");
      std::vector<double> lower, upper;
      std::vector<int> periodic;
      read_array(group, "lower", lower, 3);
      read_array(group, "upper", upper, 3);
      read_array(group, "periodic", periodic, 3);
      Domain domain;
      for (int a = 0; a < 3; ++a)
      {
        domain.lower[a] = lower[a];
        domain.upper[a] = upper[a];
        domain.periodic[a] = periodic[a] != 0;
      }
      return domain;
    }

    void write_energy(const hdf5::Handle &root, const EnergyLedger &ledger)
    {
      const hdf5::Handle group = hdf5::create_group(root.id, "energy");
      hdf5::write_string_attribute(group.id, "units", "J");
      energy_fields(ledger, [&](const char *name, double value) { write_attribute(group, name, value); });
    }

    void write_header(const hdf5::Handle &root, const char *format, const DemSystem &system)
    {
      hdf5::write_string_attribute(root.id, "format", format);
      write_attribute(root, "version", format_version);
      hdf5::write_string_attribute(root.id, "units", "SI: m, kg, s, N, Pa, J; time and dt in s");
      write_attribute(root, "time", system.time);
      write_attribute(root, "step", system.step_count);
      write_attribute(root, "dt", system.dt);
    }

    void require_format(const hdf5::Handle &root, const char *format)
    {
      const std::string found = hdf5::read_string_attribute(root.id, "format");
      if (found != format)
        fail(hdf5::location(root.id) + "@format", "is \"" + found + "\", expected \"" + format + "\"");
      const int version = read_attribute<int>(root, "version");
      if (version != format_version)
        fail(hdf5::location(root.id) + "@version",
             "is " + std::to_string(version) + ", this build reads version " + std::to_string(format_version));
    }
  } // namespace

  void write_snapshot(const std::string &file, const DemSystem &system)
  {
    hdf5::write_file_atomically(file, [&](const hdf5::Handle &root) {
      write_header(root, snapshot_format, system);
      const ParticleStore &particles = system.particles;
      const hdf5::Handle particle_group = create_array_group(root, "particles", particles.size());
      particle_arrays(particles, array_writer(particle_group));

      const BondList &bonds = system.bonds;
      const hdf5::Handle bond_group = create_array_group(root, "bonds", bonds.size());
      bond_state_arrays(bonds, array_writer(bond_group));
      std::vector<double> sigma(bonds.size()), tau(bonds.size());
      for (Index b = 0; b < bonds.size(); ++b)
        std::tie(sigma[b], tau[b]) = bonds.rim_stresses(b);
      write_array(bond_group, "sigma", sigma, "Pa");
      write_array(bond_group, "tau", tau, "Pa");

      write_domain(root, system.domain);
      write_table(root, "walls", system.walls, [](auto &&visit) { wall_fields(visit); });
      write_energy(root, system.energy());
    });
  }

  void write_checkpoint(const std::string &file, const DemSystem &system)
  {
    hdf5::write_file_atomically(file, [&](const hdf5::Handle &root) {
      write_header(root, checkpoint_format, system);
      write_attribute(root, "initial_balance", system.initial_balance);

      const hdf5::Handle particles = create_array_group(root, "particles", system.particles.size());
      particle_arrays(system.particles, array_writer(particles));
      write_array(particles, "previous_velocity", system.previous_velocity, "m/s");
      write_array(particles, "previous_angular_velocity", system.previous_angular_velocity, "rad/s");
      write_array(particles, "neighbor_reference_position", system.neighbor_reference_positions(), "m");
      write_attribute(root, "critical_time_step", system.critical_time_step_estimate());

      const hdf5::Handle contacts = create_array_group(root, "contacts", system.contacts.size());
      contact_arrays(system.contacts, array_writer(contacts));

      const hdf5::Handle bonds = create_array_group(root, "bonds", system.bonds.size());
      bond_state_arrays(system.bonds, array_writer(bonds));
      bond_restart_arrays(system.bonds, array_writer(bonds));

      write_table(root, "clumps", system.clumps, [](auto &&visit) { clump_fields(visit); });
      write_table(root, "walls", system.walls, [](auto &&visit) { wall_fields(visit); });
      write_array(root, "wall_shear", system.wall_shear, "N");
      write_array(root, "wall_dashpot", system.wall_dashpot, "N");
      write_domain(root, system.domain);

      const hdf5::Handle settings = hdf5::create_group(root.id, "settings");
      settings_fields(system.settings,
                      [&](const char *name, const auto &value) { write_attribute(settings, name, value); });
      write_energy(root, system.ledger);
    }, /*durable=*/true);
  }

  ExternalSample read_sample(const std::string &file)
  {
    const hdf5::QuietErrors quiet; // errors are reported through our exceptions
    const hdf5::Handle root = hdf5::open_file_read_only(file);
    ExternalSample sample;
    const hdf5::Handle particles = hdf5::open_group(root.id, "particles");
    read_array(particles, "position", sample.position, any_rows);
    const auto n = static_cast<Index>(sample.position.size());
    read_array(particles, "radius", sample.radius, n);
    for (Index p = 0; p < n; ++p)
      if (!(sample.radius[p] > 0))
        fail(hdf5::location(particles.id, "radius"), "sphere " + std::to_string(p) + " has radius " +
                                          std::to_string(sample.radius[p]) + " m; radii must be positive");
    if (hdf5::exists(particles.id, "clump_id"))
      read_array(particles, "clump_id", sample.clump_id, n);
    if (!hdf5::exists(root.id, "bonds"))
      return sample;
    const hdf5::Handle bonds = hdf5::open_group(root.id, "bonds");
    std::vector<Index> i, j;
    read_array(bonds, "i", i, any_rows);
    const auto m = static_cast<Index>(i.size());
    read_array(bonds, "j", j, m);
    check_range(bonds, "i", i, 0, n, "bond ends name spheres of the file");
    check_range(bonds, "j", j, 0, n, "bond ends name spheres of the file");
    std::vector<std::uint8_t> state(m, 0);
    if (hdf5::exists(bonds.id, "state"))
      read_array(bonds, "state", state, m);
    std::vector<double> radius;
    if (hdf5::exists(bonds.id, "area"))
    {
      read_array(bonds, "area", radius, m);
      for (double &r : radius)
        r = r > 0 ? std::sqrt(r / M_PI) : r; // R_bar = sqrt(A / pi)
    }
    else if (hdf5::exists(bonds.id, "radius"))
      read_array(bonds, "radius", radius, m);
    for (Index b = 0; b < m; ++b)
    {
      if (state[b] != 0)
        continue;
      if (!radius.empty() && !(radius[b] > 0))
        fail(hdf5::location(bonds.id, hdf5::exists(bonds.id, "area") ? "area" : "radius"),
             "bond " + std::to_string(b) + " has a non-positive cross-section");
      sample.bond_i.push_back(i[b]);
      sample.bond_j.push_back(j[b]);
      if (!radius.empty())
        sample.bond_radius.push_back(radius[b]);
    }
    return sample;
  }

  void read_checkpoint(const std::string &file, DemSystem &system)
  {
    const hdf5::QuietErrors quiet; // errors are reported through our exceptions
    const hdf5::Handle root = hdf5::open_file_read_only(file);
    require_format(root, checkpoint_format);

    // Read into a staging system and move into `system` only once everything has been validated.
    DemSystem staged;
    read_attribute(root, "time", staged.time);
    read_attribute(root, "step", staged.step_count);
    read_attribute(root, "dt", staged.dt);
    read_attribute(root, "initial_balance", staged.initial_balance);

    const hdf5::Handle particles = hdf5::open_group(root.id, "particles");
    const Index n = read_count(particles);
    staged.particles.resize(n);
    particle_arrays(staged.particles, array_reader(particles, n));
    read_array(particles, "previous_velocity", staged.previous_velocity, any_rows);
    read_array(particles, "previous_angular_velocity", staged.previous_angular_velocity, any_rows);
    check_empty_or_rows(particles, "previous_velocity", staged.previous_velocity, n);
    check_empty_or_rows(particles, "previous_angular_velocity", staged.previous_angular_velocity, n);
    std::vector<Vec3> neighbor_reference;
    read_array(particles, "neighbor_reference_position", neighbor_reference, any_rows);
    check_empty_or_rows(particles, "neighbor_reference_position", neighbor_reference, n);
    double critical_time_step = 0;
    read_attribute(root, "critical_time_step", critical_time_step);

    const hdf5::Handle contacts = hdf5::open_group(root.id, "contacts");
    const Index contact_count = read_count(contacts);
    contact_arrays(staged.contacts, array_reader(contacts, contact_count));
    staged.contacts.load.assign(contact_count, PairLoad{});

    const hdf5::Handle bonds = hdf5::open_group(root.id, "bonds");
    const Index bond_count = read_count(bonds);
    staged.bonds.resize(bond_count);
    bond_state_arrays(staged.bonds, array_reader(bonds, bond_count));
    bond_restart_arrays(staged.bonds, array_reader(bonds, bond_count));

    read_table(root, "clumps", staged.clumps, [](auto &&visit) { clump_fields(visit); });
    read_table(root, "walls", staged.walls, [](auto &&visit) { wall_fields(visit); });
    read_array(root, "wall_shear", staged.wall_shear, any_rows);
    check_empty_or_rows(root, "wall_shear", staged.wall_shear, static_cast<Index>(staged.walls.size()) * n);
    read_array(root, "wall_dashpot", staged.wall_dashpot, any_rows);
    check_empty_or_rows(root, "wall_dashpot", staged.wall_dashpot, static_cast<Index>(staged.walls.size()) * n);
    staged.domain = read_domain(root);

    const hdf5::Handle settings = hdf5::open_group(root.id, "settings");
    settings_fields(staged.settings,
                    [&](const char *name, auto &value) { read_attribute(settings, name, value); });
    const hdf5::Handle energy = hdf5::open_group(root.id, "energy");
    energy_fields(staged.ledger, [&](const char *name, double &value) { read_attribute(energy, name, value); });

    // --- cross references
    const auto clump_count = static_cast<Index>(staged.clumps.size());
    check_range(particles, "material_id", staged.particles.material_id, 0, system.materials.size(),
                "material ids name materials of the scene, which checkpoints do not store (the system "
                "read into defines " + std::to_string(system.materials.size()) + ")");
    check_range(particles, "clump_id", staged.particles.clump_id, -1, clump_count,
                "clump ids are -1 or name a stored clump");
    const std::string particle_rule = "indices name stored particles";
    const auto check_pair_indices = [&](const hdf5::Handle &group, const auto &pairs) {
      check_range(group, "i", pairs.i, 0, n, particle_rule);
      check_range(group, "j", pairs.j, 0, n, particle_rule);
    };
    check_pair_indices(contacts, staged.contacts);
    check_pair_indices(bonds, staged.bonds);
    for (const BondState state : staged.bonds.state)
      if (to_stored(state) > to_stored(BondState::broken_shear))
        fail(hdf5::location(bonds.id, "state"), "unknown bond state " + std::to_string(to_stored(state)));
    const hdf5::Handle clumps = hdf5::open_group(root.id, "clumps");
    for (const Clump &clump : staged.clumps)
    {
      check_range(clumps, "members", clump.members, 0, n, particle_rule);
      if (clump.members.size() != clump.member_offset.size() ||
          clump.applied_force.time.size() != clump.applied_force.value.size())
        fail(hdf5::location(clumps.id), "the counts of members and member_offset, or of applied_force_time and "
                             "applied_force_value, differ");
    }

    // --- commit (materials stay; derived data is rebuilt by resume())
    system.particles = std::move(staged.particles);
    system.previous_velocity = std::move(staged.previous_velocity);
    system.previous_angular_velocity = std::move(staged.previous_angular_velocity);
    system.contacts = std::move(staged.contacts);
    system.bonds = std::move(staged.bonds);
    system.clumps = std::move(staged.clumps);
    system.walls = std::move(staged.walls);
    system.wall_shear = std::move(staged.wall_shear);
    system.wall_dashpot = std::move(staged.wall_dashpot);
    system.domain = staged.domain;
    system.settings = staged.settings;
    system.ledger = staged.ledger;
    system.time = staged.time;
    system.step_count = staged.step_count;
    system.dt = staged.dt;
    system.initial_balance = staged.initial_balance;
    system.restore_neighbor_reference_positions(std::move(neighbor_reference));
    system.restore_critical_time_step_estimate(critical_time_step);
  }
} // namespace anticrack::dem::io
