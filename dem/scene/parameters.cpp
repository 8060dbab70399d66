#include "dem/scene/parameters.h"


#include "util/sha256.h"
#include "dem/contact/contact_law.h"
#include "util/input_error.h"
#include "util/parameter_files.h"
#include "util/parameter_input.h"
#include "util/problems.h"
#include "dem/scene/scene_entries.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <sstream>
#include <utility>

namespace anticrack::dem
{
  using dealii::ParameterHandler;

  namespace
  {
    /// An entry that may be left empty: Patterns::List of zero or one double, empty by default.
    void declare_optional_double(ParameterHandler &prm, const std::string &name, const std::string &documentation)
    {
      prm.declare_entry(name, "", Patterns::List(Patterns::Double(), 0, 1), documentation);
    }

    std::optional<double> get_optional_double(const ParameterHandler &prm, const std::string &name)
    {
      const std::string value = dealii::Utilities::trim(prm.get(name));
      if (value.empty())
        return std::nullopt;
      return dealii::Utilities::string_to_double(value);
    }
  } // namespace

  std::string format_vector(const Vec3 &v)
  {
    return format_number(v[0]) + ", " + format_number(v[1]) + ", " + format_number(v[2]);
  }

  namespace parameters
  {
    // ------------------------------------------------------------------------------- Output
    void Output::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      prm.declare_entry("Snapshot interval [steps]", "0", Patterns::Integer(0),
                        "Steps between HDF5 snapshots snapshots/snapshot_NNNNNN.h5 (the state for "
                        "post-processing; NNNNNN is the step). When positive, snapshots are also "
                        "written at the first and the last step. 0 writes none.");
      prm.declare_entry("Checkpoint interval [steps]", "0", Patterns::Integer(0),
                        "Steps between restart files checkpoint.h5 (overwritten each time, plus "
                        "checkpoint.json with the scene's hash); `anticrack run --resume` continues "
                        "from the last one. When positive, a checkpoint is also written at the last "
                        "step. 0 writes none.");
      prm.declare_entry("History interval [steps]", "100", Patterns::Integer(0),
                        "Steps between rows of the time series history.h5 (energies, bonds, wall "
                        "stresses, clump motion). The first and last steps are always recorded; "
                        "0 records only those.");
      prm.declare_entry("Progress interval [steps]", "1000", Patterns::Integer(0),
                        "Steps between progress reports on the console. 0 is quiet.");
      prm.declare_entry("Write ParaView", "false", Patterns::Bool(),
                        "Write paraview/particles_NNNNNN.vtp and bonds_NNNNNN.vtp with "
                        "particles.pvd and bonds.pvd collections at every snapshot step.");
      prm.leave_subsection();
    }

    void Output::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      snapshot_interval = prm.get_integer("Snapshot interval [steps]");
      checkpoint_interval = prm.get_integer("Checkpoint interval [steps]");
      history_interval = prm.get_integer("History interval [steps]");
      progress_interval = prm.get_integer("Progress interval [steps]");
      write_paraview = prm.get_bool("Write ParaView");
      prm.leave_subsection();
    }

    void Output::check(Problems &problems) const
    {
      if (write_paraview && snapshot_interval == 0)
        problems.add("Output/Write ParaView", "true",
                     "ParaView files are written at the snapshot steps: set Output/Snapshot "
                     "interval [steps] > 0");
    }

    // ------------------------------------------------------------------------------- Domain
    void Domain::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Domain");
      declare_vector(prm, "Lower corner [m]", "0, 0, 0",
                     "x_min: lower corner of the axis-aligned simulation box. Units: m.");
      declare_vector(prm, "Upper corner [m]", "0.02, 0.02, 0.02",
                     "x_max: upper corner of the simulation box, above the lower corner along "
                     "every axis. Units: m.");
      prm.declare_entry("Periodic axes", "", Patterns::MultipleSelection("x|y|z"),
                        "Axes along which the box is periodic (a comma-separated subset of x, y, "
                        "z; empty for none). Contacts and bonds across a periodic face use the "
                        "minimum image; walls cannot sit on a periodic axis.");
      prm.leave_subsection();
    }

    void Domain::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Domain");
      lower = get_triple<Vec3>(prm, "Lower corner [m]");
      upper = get_triple<Vec3>(prm, "Upper corner [m]");
      periodic = {false, false, false};
      for (const auto &axis : dealii::Utilities::split_string_list(prm.get("Periodic axes"), ','))
        periodic[axis == "x" ? 0 : axis == "y" ? 1 : 2] = true;
      prm.leave_subsection();
    }

    void Domain::check(Problems &problems) const
    {
      for (int a = 0; a < 3; ++a)
        if (!(length()[a] > 0))
          problems.add("DEM/Domain/Upper corner [m]", vec(upper),
                       std::string("must exceed DEM/Domain/Lower corner [m] = ") + vec(lower) + " along " +
                         axis_name[a]);
    }

    // ----------------------------------------------------------------------------- Material
    void Material::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Material");
      prm.declare_entry("Density [kg/m^3]", "1e4", Patterns::Double(0),
                        "rho: density of the spheres (Ritter et al. (2020) use 10 000 kg/m^3 without "
                        "gravity to speed up quasi-static tests). Units: kg/m^3.");
      prm.declare_entry("Contact law", "linear", Patterns::Selection(dem::contact_law_names()),
                        "Force-overlap law of sphere-sphere and sphere-wall contacts (docs/physics.md "
                        "§1.1): " + dem::contact_law_documentation() +
                          ". Every law caps the tangential force by Coulomb's law |F_s| <= mu F_n.");
      // Each law's own entries (dem/contact/NAME_contact.h), then those of friction and dashpots,
      // which every law shares (dem/contact/frictional_contact.h).
      dem::visit_contact_entries([&](const dem::ContactEntry &e) {
        prm.declare_entry(e.name, e.default_value, Patterns::Double(e.lower, e.upper), e.documentation);
      });
      prm.declare_entry("Friction coefficient", "0.5", Patterns::Double(0),
                        "mu = tan(phi_contact): Coulomb friction coefficient of contacts. Units: "
                        "none.");
      prm.declare_entry("Damping ratio", "0", Patterns::Double(0, 1),
                        "beta_d: ratio of the contact dashpots to critical damping, "
                        "c = 2 beta_d sqrt(m_eff k). 0 switches the dashpots off. Units: none.");
      prm.leave_subsection();
    }

    void Material::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Material");
      density = prm.get_double("Density [kg/m^3]");
      contact.law = dem::contact_law_by_name(prm.get("Contact law"));
      dem::visit_contact_entries([&](const dem::ContactEntry &e) { contact.*e.field = prm.get_double(e.name); });
      contact.friction = prm.get_double("Friction coefficient");
      contact.damping_ratio = prm.get_double("Damping ratio");
      prm.leave_subsection();
    }

    void Material::check(Problems &problems) const
    {
      // Moduli that patterns only bound from below by zero.
      if (!(density > 0))
        problems.add("DEM/Material/Density [kg/m^3]", density, "must be positive");
      // The chosen law's own requirements (dem/contact/NAME_contact.h).
      dem::visit_contact_entries(contact.law, [&](const dem::ContactEntry &e) {
        if (!e.acceptable(contact.*e.field))
          problems.add(std::string("DEM/Material/") + e.name, contact.*e.field, e.requirement);
      });
    }

    // --------------------------------------------------------------------------------- Bond
    void Bond::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Bond");
      prm.declare_entry("Enabled", "true", Patterns::Bool(),
                        "Whether touching spheres are joined by parallel bonds (Potyondy & "
                        "Cundall 2004; docs/physics.md §1.2) when the sample is built.");
      prm.declare_entry("Modulus [Pa]", "1e9", Patterns::Double(0),
                        "E_bar: bond modulus, k_n_bar = E_bar / L per unit area with "
                        "L = R_i + R_j. Units: Pa.");
      prm.declare_entry("Stiffness ratio", "3", Patterns::Double(0),
                        "kappa_bar = k_n_bar / k_s_bar: normal-to-shear stiffness ratio of the "
                        "bond. Units: none.");
      prm.declare_entry("Radius multiplier", "1", Patterns::Double(0),
                        "lambda_bar: bond radius R_bar = lambda_bar min(R_i, R_j). Units: none.");
      prm.declare_entry("Tensile strength [Pa]", "1e6", Patterns::Double(0),
                        "sigma_bar_c: the bond breaks in tension when the rim stress "
                        "sigma_bar = -F_n/A + beta_bar |M_b| R_bar / I >= sigma_bar_c. Units: Pa.");
      prm.declare_entry("Cohesion [Pa]", "1e6", Patterns::Double(0),
                        "c_bar: the bond breaks in shear when the rim stress "
                        "tau_bar = |F_s|/A + beta_bar |M_t| R_bar / J >= c_bar - sigma_bar "
                        "tan(phi_bar). Units: Pa.");
      prm.declare_entry("Friction angle [deg]", "0", Patterns::Double(0, 90),
                        "phi_bar: friction angle of the bond's shear strength, below 90. Units: "
                        "degrees.");
      prm.declare_entry("Moment contribution factor", "1", Patterns::Double(0, 1),
                        "beta_bar: weight of the bending and twisting moments in the rim "
                        "stresses; 1 is the original parallel bond. Units: none.");
      prm.declare_entry("Gap tolerance", "1e-6", Patterns::Double(0),
                        "Pairs whose gap d - R_i - R_j is at most this times min(R_i, R_j) are "
                        "bonded (overlapping pairs are bonded too). Units: none (relative to the "
                        "smaller radius).");
      prm.leave_subsection();
    }

    void Bond::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Bond");
      bond.enabled = prm.get_bool("Enabled");
      bond.modulus = prm.get_double("Modulus [Pa]");
      bond.stiffness_ratio = prm.get_double("Stiffness ratio");
      bond.radius_multiplier = prm.get_double("Radius multiplier");
      bond.tensile_strength = prm.get_double("Tensile strength [Pa]");
      bond.cohesion = prm.get_double("Cohesion [Pa]");
      friction_angle_deg = prm.get_double("Friction angle [deg]");
      bond.friction_angle = friction_angle_deg * M_PI / 180.0;
      bond.moment_factor = prm.get_double("Moment contribution factor");
      gap_tolerance = prm.get_double("Gap tolerance");
      prm.leave_subsection();
    }

    void Bond::check(Problems &problems) const
    {
      if (!bond.enabled)
        return;
      if (!(bond.modulus > 0))
        problems.add("DEM/Bond/Modulus [Pa]", bond.modulus, "must be positive");
      if (!(bond.stiffness_ratio > 0))
        problems.add("DEM/Bond/Stiffness ratio", bond.stiffness_ratio, "must be positive");
      if (!(bond.radius_multiplier > 0))
        problems.add("DEM/Bond/Radius multiplier", bond.radius_multiplier, "must be positive");
      if (!(friction_angle_deg < 90))
        problems.add("DEM/Bond/Friction angle [deg]", friction_angle_deg, "must be below 90");
    }

    // ------------------------------------------------------------------------------- Sample
    void Sample::declare_parameters(ParameterHandler &prm, const SampleType *type)
    {
      prm.enter_subsection("Sample");
      declare_variants(prm, "Type", sample_types(), type, shared_sample_entries(), sample_type_documentation());
      prm.leave_subsection();
    }

    void Sample::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Sample");
      type = &row_named(sample_types(), prm.get("Type"));
      parse_shared_sample_entries(prm, *this);
      type->parse_parameters(prm, *this);
      prm.leave_subsection();
    }

    void Sample::check(Problems &problems, const Dem &dem) const { type->check(*this, dem, problems); }

    // -------------------------------------------------------------------------- Integration
    void Integration::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Integration");
      declare_vector(prm, "Gravity [m/s^2]", "0, 0, 0", "g: gravitational acceleration. Units: m/s^2.");
      prm.declare_entry("Local damping", "0.7", Patterns::Double(0, 1),
                        "alpha: Cundall's local damping, F_w <- F_w - alpha |F_w| sign(v_w) for "
                        "every force and moment component (PFC default 0.7; 0 is undamped). "
                        "0 <= alpha < 1. Units: none.");
      prm.declare_entry("Time step [s]", "0", Patterns::Double(0),
                        "dt: fixed time step; 0 selects the automatic step "
                        "dt = safety factor x dt_crit, re-evaluated every `Time step update "
                        "interval` steps. Units: s.");
      prm.declare_entry("Time step safety factor", "0.5", Patterns::Double(0, 1),
                        "Fraction of the critical step dt_crit = min(sqrt(m/K), sqrt(I/K_rot)) "
                        "used in automatic mode, in (0, 1]. Units: none.");
      prm.declare_entry("Enforce critical time step", "true", Patterns::Bool(),
                        "Refuse a fixed time step above the critical estimate.");
      prm.declare_entry("Time step update interval [steps]", "100", Patterns::Integer(1),
                        "Steps between re-evaluations of the critical time step.");
      prm.declare_entry("Verlet skin [m]", "0", Patterns::Double(0),
                        "Extra distance of the Verlet neighbour list; the list is rebuilt when a "
                        "sphere has moved more than half of it. 0 selects 0.1 x mean radius. "
                        "Units: m.");
      prm.declare_entry("Energy drift tolerance", "0.25", Patterns::Double(0),
                        "The run stops with a numerical error when the energy balance "
                        "kinetic + elastic + potential + dissipated - external work drifts from "
                        "its initial value by more than this fraction. Units: none.");
      prm.declare_entry("Stability check interval [steps]", "100", Patterns::Integer(1),
                        "Steps between checks of the energy balance and of NaNs.");
      prm.leave_subsection();
    }

    void Integration::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Integration");
      settings.gravity = get_triple<Vec3>(prm, "Gravity [m/s^2]");
      settings.local_damping = prm.get_double("Local damping");
      settings.time_step = prm.get_double("Time step [s]");
      settings.time_step_safety = prm.get_double("Time step safety factor");
      settings.enforce_critical_step = prm.get_bool("Enforce critical time step");
      settings.time_step_interval = prm.get_integer("Time step update interval [steps]");
      settings.verlet_skin = prm.get_double("Verlet skin [m]");
      settings.energy_drift_tolerance = prm.get_double("Energy drift tolerance");
      settings.stability_check_interval = prm.get_integer("Stability check interval [steps]");
      prm.leave_subsection();
    }

    void Integration::check(Problems &problems) const
    {
      if (!(settings.local_damping < 1))
        problems.add("DEM/Integration/Local damping", settings.local_damping, "must be below 1");
      if (!(settings.time_step_safety > 0))
        problems.add("DEM/Integration/Time step safety factor", settings.time_step_safety,
                     "must be in (0, 1]");
    }

    // -------------------------------------------------------------------------------- Walls
    const EnumTable<dem::WallControl> &wall_control_names()
    {
      static const EnumTable<dem::WallControl> names{{"fixed", dem::WallControl::fixed},
                                                     {"velocity", dem::WallControl::velocity},
                                                     {"servo", dem::WallControl::servo}};
      return names;
    }

    void WallFace::declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Active", "false", Patterns::Bool(),
                        "Whether a planar wall sits on this face of the domain, pushing spheres "
                        "inwards with the contact law of DEM/Material (linear law: L = R, "
                        "A = pi R^2).");
      prm.declare_entry("Control", "fixed", Patterns::Selection(wall_control_names().pattern()),
                        "`fixed`: the wall stays put. `velocity`: it moves at `Velocity` along "
                        "its inward normal. `servo`: its normal velocity is "
                        "gain (sigma_target A - F_n), capped at `Max speed`, with A the face area.");
      prm.declare_entry("Velocity [m/s]", "0", Patterns::Double(),
                        "v: wall speed along the inward normal (positive compresses the sample). "
                        "Units: m/s.");
      prm.declare_entry("Target stress [Pa]", "0", Patterns::Double(0),
                        "sigma_target: compressive normal stress held by a servo wall. Units: Pa.");
      prm.declare_entry("Servo gain [m/(s N)]", "0", Patterns::Double(0),
                        "G: servo wall speed per unit force error. Units: m/(s N).");
      prm.declare_entry("Max speed [m/s]", "0", Patterns::Double(0),
                        "Cap on the servo wall speed. Units: m/s.");
    }

    void WallFace::parse_parameters(ParameterHandler &prm)
    {
      active = prm.get_bool("Active");
      control = wall_control_names().value(prm.get("Control"));
      velocity = prm.get_double("Velocity [m/s]");
      target_stress = prm.get_double("Target stress [Pa]");
      servo_gain = prm.get_double("Servo gain [m/(s N)]");
      max_speed = prm.get_double("Max speed [m/s]");
    }

    namespace
    {
      /// Calls body(f) inside subsection Walls/<face_names[f]> for every face f, in that order.
      template <class Body>
      void for_each_wall_face(ParameterHandler &prm, Body &&body)
      {
        prm.enter_subsection("Walls");
        for (int f = 0; f < 6; ++f)
        {
          prm.enter_subsection(Walls::face_names[f]);
          body(f);
          prm.leave_subsection();
        }
        prm.leave_subsection();
      }
    } // namespace

    void Walls::declare_parameters(ParameterHandler &prm)
    {
      for_each_wall_face(prm, [&](int) { WallFace::declare_parameters(prm); });
    }

    void Walls::parse_parameters(ParameterHandler &prm)
    {
      for_each_wall_face(prm, [&](int f) { face[f].parse_parameters(prm); });
    }

    void Walls::check(Problems &problems, const Domain &domain) const
    {
      for (int f = 0; f < 6; ++f)
      {
        const WallFace &wall = face[f];
        if (!wall.active)
          continue;
        const int a = axis(f);
        if (domain.periodic[a])
          problems.add(path(f) + "/Active", "true",
                       std::string("a wall cannot sit on the periodic axis ") + axis_name[a] +
                         " (see DEM/Domain/Periodic axes)");
        if (wall.control == dem::WallControl::servo)
        {
          if (!(wall.servo_gain > 0))
            problems.add(path(f) + "/Servo gain [m/(s N)]", wall.servo_gain,
                         "must be positive for a servo-controlled wall");
          if (!(wall.max_speed > 0))
            problems.add(path(f) + "/Max speed [m/s]", wall.max_speed,
                         "must be positive for a servo-controlled wall");
        }
      }
    }

    // ------------------------------------------------------------------- Boundary particles
    void BoundaryParticles::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Boundary particles");
      declare_optional_double(prm, "Fix below [m]",
                              "Spheres whose centre has z below this are fixed (no translation, no "
                              "rotation) and form the base; their reactions give the base stresses in "
                              "history.h5. Empty for none. Units: m.");
      declare_optional_double(prm, "Clump above [m]",
                              "Spheres whose centre has z above this form one rigid clump (the loading "
                              "platen of docs/physics.md §1.5). Empty for none. Units: m.");
      declare_optional_double(prm, "Base thickness [mean radii]",
                              "t_b: alternative to Fix below [m] in units of the mean radius R: spheres "
                              "whose centre lies below the domain's lower z + t_b R are fixed (Ritter et al. 2020: "
                              "t_b = 3, 'z_p0 < 3r'). Empty for none.");
      declare_optional_double(prm, "Actuator thickness [mean radii]",
                              "t_a: alternative to Clump above [m] in units of the mean radius R: spheres "
                              "whose centre lies above z_top - t_a R form the clump, with z_top the lower "
                              "of the domain's upper z and the highest sphere top. Empty for none.");
      prm.declare_entry("Clump force rate [N/s]", "0", Patterns::Double(),
                        "Fdot: the clump is loaded by F(t) = Fdot t d at its centre of mass. "
                        "Units: N/s.");
      declare_vector(prm, "Clump force direction", "0, 0, -1",
                     "d: direction of the clump force, normalised to unit length; the "
                     "mixed-mode test at angle psi uses d = (sin psi, 0, -cos psi). Units: "
                     "none.");
      prm.declare_entry("Clump rotation locked", "false", Patterns::Bool(),
                        "Keep the clump from rotating (a guided platen).");
      prm.leave_subsection();
    }

    void BoundaryParticles::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Boundary particles");
      fix_below = get_optional_double(prm, "Fix below [m]");
      clump_above = get_optional_double(prm, "Clump above [m]");
      base_thickness = get_optional_double(prm, "Base thickness [mean radii]");
      actuator_thickness = get_optional_double(prm, "Actuator thickness [mean radii]");
      clump_force_rate = prm.get_double("Clump force rate [N/s]");
      clump_force_direction = get_triple<Vec3>(prm, "Clump force direction");
      if (clump_force_direction.norm() > 0)
        clump_force_direction.normalize();
      clump_rotation_locked = prm.get_bool("Clump rotation locked");
      prm.leave_subsection();
    }

    void BoundaryParticles::check(Problems &problems) const
    {
      if (fix_below && clump_above && *clump_above < *fix_below)
        problems.add("DEM/Boundary particles/Clump above [m]", *clump_above,
                     "must not be below DEM/Boundary particles/Fix below [m] = " + format_number(*fix_below) +
                       ": a sphere cannot be fixed and clumped");
      if (clump_above && clump_force_rate != 0 && clump_force_direction.norm() == 0)
        problems.add("DEM/Boundary particles/Clump force direction", vec(clump_force_direction),
                     "must be a nonzero vector when the clump force rate is nonzero");
      if (fix_below && base_thickness)
        problems.add("DEM/Boundary particles/Base thickness [mean radii]", *base_thickness,
                     "and Fix below [m] both select the base; leave one of them empty");
      if (clump_above && actuator_thickness)
        problems.add("DEM/Boundary particles/Actuator thickness [mean radii]", *actuator_thickness,
                     "and Clump above [m] both select the clump; leave one of them empty");
      for (const auto &[name, value] : {std::pair{"Base thickness [mean radii]", base_thickness},
                                        {"Actuator thickness [mean radii]", actuator_thickness}})
        if (value && !(*value > 0))
          problems.add(std::string("DEM/Boundary particles/") + name, *value, "must be positive");
    }

    // ------------------------------------------------------------------------------ Loading
    void Loading::declare_parameters(ParameterHandler &prm, const LabTest *test)
    {
      prm.enter_subsection("Loading");
      declare_variants(prm, "Test", lab_tests(), test, shared_loading_entries(), lab_test_documentation());
      prm.leave_subsection();
    }

    void Loading::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Loading");
      test = &row_named(lab_tests(), prm.get("Test"));
      parse_shared_loading_entries(prm, *this);
      test->parse_parameters(prm, *this);
      prm.leave_subsection();
    }

    void Loading::check(Problems &problems, const Dem &dem) const { test->check(*this, dem, problems); }

    // ------------------------------------------------------------------------------ Bedding
    void Bedding::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Bedding");
      prm.declare_entry("Enabled", "false", Patterns::Bool(),
                        "Give the bonds that cross bedding planes their own strengths (Zhao & Feng's (2022) layered "
                        "slate; dem/sample/bedding.h).");
      prm.declare_entry("Inclination [deg]", "0", Patterns::Double(-90, 90),
                        "theta: angle between the bedding planes and the x-y plane (rotation about y): "
                        "0 = planes normal to z, 90 = planes normal to x. Units: degrees.");
      prm.declare_entry("Spacing [m]", "2e-3", Patterns::Double(0),
                        "Distance between neighbouring bedding planes. Units: m.");
      prm.declare_entry("Offset [m]", "0", Patterns::Double(),
                        "n.x of the plane k = 0. Units: m.");
      prm.declare_entry("Thickness [m]", "0", Patterns::Double(0),
                        "Thickness of the band around each plane whose bonds are weakened (0: bonds that "
                        "cross the plane itself). Units: m.");
      prm.declare_entry("Tensile strength [Pa]", "1e5", Patterns::Double(0),
                        "sigma_bar_c of bedding bonds. Units: Pa.");
      prm.declare_entry("Cohesion [Pa]", "1e5", Patterns::Double(0), "c_bar of bedding bonds. Units: Pa.");
      prm.declare_entry("Friction angle [deg]", "0", Patterns::Double(0, 90),
                        "phi_bar of bedding bonds. Units: degrees.");
      prm.leave_subsection();
    }

    void Bedding::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Bedding");
      enabled = prm.get_bool("Enabled");
      inclination_deg = prm.get_double("Inclination [deg]");
      const double theta = inclination_deg * M_PI / 180.0;
      spec.normal = Vec3(std::sin(theta), 0.0, std::cos(theta));
      spec.spacing = prm.get_double("Spacing [m]");
      spec.offset = prm.get_double("Offset [m]");
      spec.thickness = prm.get_double("Thickness [m]");
      spec.tensile_strength = prm.get_double("Tensile strength [Pa]");
      spec.cohesion = prm.get_double("Cohesion [Pa]");
      spec.friction_angle = prm.get_double("Friction angle [deg]") * M_PI / 180.0;
      prm.leave_subsection();
    }

    void Bedding::check(Problems &problems, const Bond &bond) const
    {
      if (!enabled)
        return;
      if (!bond.bond.enabled)
        problems.add("DEM/Bedding/Enabled", "true", "weakens bonds: DEM/Bond/Enabled must be true");
      if (!(spec.spacing > 0))
        problems.add("DEM/Bedding/Spacing [m]", spec.spacing, "must be positive");
    }

    // ---------------------------------------------------------------------------------- DEM
    void Dem::declare_parameters(ParameterHandler &prm, const Declaration &declaration)
    {
      prm.enter_subsection("DEM");
      prm.declare_entry("Steps", "1000", Patterns::Integer(1),
                        "Number of time steps of the run (a resumed run continues up to this "
                        "count).");
      prm.declare_entry("Threads", "0", Patterns::Integer(0),
                        "OpenMP threads of the force and update loops; 0 uses all available "
                        "(OMP_NUM_THREADS or every core). `anticrack run --threads` overrides it. "
                        "Results do not depend on it.");
      prm.declare_entry("Random seed", "1", Patterns::Integer(0),
                        "Seed of the random initial velocities.");
      Domain::declare_parameters(prm);
      Material::declare_parameters(prm);
      Bond::declare_parameters(prm);
      // One variant (its index in the table), or every one (null).
      const auto variant = [](const std::optional<int> index, const auto &variants) {
        return index ? &variants.at(*index) : nullptr;
      };
      Sample::declare_parameters(prm, variant(declaration.sample_type, sample_types()));
      Integration::declare_parameters(prm);
      Walls::declare_parameters(prm);
      BoundaryParticles::declare_parameters(prm);
      Loading::declare_parameters(prm, variant(declaration.loading_test, lab_tests()));
      Bedding::declare_parameters(prm);
      prm.leave_subsection();
    }

    void Dem::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("DEM");
      steps = prm.get_integer("Steps");
      threads = static_cast<int>(prm.get_integer("Threads"));
      seed = static_cast<std::uint64_t>(prm.get_integer("Random seed"));
      domain.parse_parameters(prm);
      material.parse_parameters(prm);
      bond.parse_parameters(prm);
      sample.parse_parameters(prm);
      integration.parse_parameters(prm);
      walls.parse_parameters(prm);
      boundary.parse_parameters(prm);
      loading.parse_parameters(prm);
      loading.ramp.fast_rate = boundary.clump_force_rate;
      bedding.parse_parameters(prm);
      prm.leave_subsection();
    }
  } // namespace parameters

  const EnumTable<SceneKind> &scene_kind_names()
  {
    static const EnumTable<SceneKind> names{
      {"dem", SceneKind::dem}, {"campaign", SceneKind::campaign}, {"calibration", SceneKind::calibration}};
    return names;
  }

  void SceneParameters::declare_parameters(ParameterHandler &prm, const Declaration &declaration)
  {
    // The kind is read by app/scenes.cpp before this declaration; declaring it here lets the file
    // say it, and makes `anticrack params --scene KIND` print a scene of that kind.
    const std::string kind = scene_kind_names().name(declaration.kind.value_or(SceneKind::dem));
    prm.declare_entry("Scene", kind,
                      Patterns::Selection(declaration.kind ? kind : scene_kind_names().pattern()),
                      "What the scene is: `dem` one DEM run, `campaign` the DEM test at every loading "
                      "angle x realization x microstructure (subsection Campaign), `calibration` a "
                      "campaign and the continuum material calibrated from it (subsection Calibration). "
                      "Snowpack (FE) scenes say `snowpack`. A scene without it is read as the kind its "
                      "subsections suggest, with a note.");
    prm.declare_entry("Components", "dem", Patterns::MultipleSelection("dem"),
                      "Kept for scenes written before `Scene`: `dem` is the bonded-particle simulation.");
    parameters::Output::declare_parameters(prm);
    parameters::Dem::declare_parameters(prm, declaration);
    if (declaration.declares_campaign())
      parameters::Campaign::declare_parameters(prm);
    if (declaration.declare_more)
      declaration.declare_more(prm);
  }

  void SceneParameters::parse_parameters(ParameterHandler &prm)
  {
    kind = scene_kind_names().value(prm.get("Scene"));
    components = dealii::Utilities::split_string_list(prm.get("Components"), ',');
    output.parse_parameters(prm);
    dem.parse_parameters(prm);
    if (kind != SceneKind::dem)
      campaign.parse_parameters(prm);
  }

  // ------------------------------------------------------------------- cross-subsection rules
  namespace
  {
    // The clump comes from DEM/Boundary particles (Clump above [m] or Actuator thickness) or from
    // the actuator layer of DEM/Sample, and DEM/Loading uses it: these rules relate subsections and
    // belong to none of them.

    /// The actuator layer against the boundary particles and the box; the loading that needs a clump.
    void check_clump_sources_and_users(const parameters::Dem &d, Problems &problems)
    {
      const auto &bp = d.boundary;
      const auto &s = d.sample;
      if (s.actuator_count > 0)
      {
        if (!s.type->has_entry("Actuator layer count"))
          problems.add("DEM/Sample/Actuator layer count", s.actuator_count,
                       "an actuator layer is deposited on a ballistic deposit only (DEM/Sample/Type)");
        if (bp.clump_above || bp.actuator_thickness)
          problems.add("DEM/Sample/Actuator layer count", s.actuator_count,
                       "the actuator layer is the clump: leave DEM/Boundary particles/Clump above [m] and "
                       "Actuator thickness [mean radii] empty");
        if (!(s.actuator_radius > 0))
          problems.add("DEM/Sample/Actuator layer radius [m]", s.actuator_radius, "must be positive");
        else
        {
          const Vec3 length = d.domain.length();
          for (int a = 0; a < 2; ++a)
            if (!(length[a] >= 8 * s.actuator_radius))
              problems.add("DEM/Sample/Actuator layer radius [m]", s.actuator_radius,
                           "the box along " + std::string(axis_name[a]) + " (" + format_number(length[a]) +
                             " m) must be at least 4 actuator diameters");
        }
      }
      if (d.loading.adaptive && !(d.has_clump() && bp.clump_force_rate > 0))
        problems.add("DEM/Loading/Adaptive rate", "true",
                     "adapts the clump force ramp: it needs a clump (DEM/Boundary particles/Clump above "
                     "[m] or Actuator thickness [mean radii]) and Clump force rate [N/s] > 0");
      if (d.loading.stop_strain > 0 && !d.has_clump())
        problems.add("DEM/Loading/Stop strain", d.loading.stop_strain,
                     "measures the clump's displacement: it needs a clump (DEM/Boundary particles)");
    }

    /// Apart from the rules above only because its message has always closed the list.
    void check_clump_force_rate_has_a_clump(const parameters::Dem &d, Problems &problems)
    {
      if (!d.has_clump() && d.boundary.clump_force_rate != 0)
        problems.add("DEM/Boundary particles/Clump force rate [N/s]", d.boundary.clump_force_rate,
                     "loads a clump, but DEM/Boundary particles/Clump above [m] is empty");
    }
  } // namespace

  void SceneParameters::check(Problems &problems) const
  {
    // The order of the calls is the order of the messages, which a user reads as one list:
    // subsection by subsection, with the clump's rules where they have always been.
    const parameters::Dem &d = dem;
    output.check(problems);
    if (components.empty())
      problems.add("Components", "(empty)", "choose at least one component (dem)");
    d.domain.check(problems);
    d.material.check(problems);
    d.bond.check(problems);
    d.sample.check(problems, d);
    d.integration.check(problems);
    d.walls.check(problems, d.domain);
    d.boundary.check(problems);
    check_clump_sources_and_users(d, problems);
    d.bedding.check(problems, d.bond);
    d.loading.check(problems, d);
    campaign.check(problems, kind, d);
    check_clump_force_rate_has_a_clump(d, problems);
  }

  namespace
  {
    /// Hash of the model-defining part of the parameters; see SceneParameters::resume_key_sha256.
    std::string resume_key(const ParameterHandler &prm)
    {
      std::ostringstream json_text;
      prm.print_parameters(json_text, ParameterHandler::ShortJSON);
      auto json = nlohmann::json::parse(json_text.str());
      json.erase("Output");
      json["DEM"].erase("Steps");
      json["DEM"].erase("Threads");
      return util::sha256_hex(json.dump());
    }
  } // namespace

  namespace
  {
    using Overrides = std::vector<std::pair<std::string, std::string>>;

    /// The kind, DEM/Sample/Type and DEM/Loading/Test of a scene (overrides included): the
    /// variants whose entries it may set. A first pass that skips every other entry.
    Declaration declaration_of(const std::string &bytes, const std::string &file, const SceneKind kind,
                               const Overrides &overrides)
    {
      ParameterHandler prm;
      prm.enter_subsection("DEM");
      prm.enter_subsection("Sample");
      prm.declare_entry("Type", sample_types().front().name, Patterns::Selection(names_pattern(sample_types())));
      prm.leave_subsection();
      prm.enter_subsection("Loading");
      prm.declare_entry("Test", lab_tests().front().name, Patterns::Selection(names_pattern(lab_tests())));
      prm.leave_subsection();
      prm.leave_subsection();
      parse_parameter_text(prm, bytes, file, "scene file", /*skip_undefined=*/true);
      for (const auto &[path, value] : overrides)
        if (path == "Sample/Type" || path == "DEM/Sample/Type" || path == "Loading/Test" || path == "DEM/Loading/Test")
        {
          const auto parts = split_parameter_path(path.rfind("DEM/", 0) == 0 ? path : "DEM/" + path);
          prm.enter_subsection(parts[0]);
          prm.enter_subsection(parts[1]);
          prm.set(parts[2], value);
          prm.leave_subsection();
          prm.leave_subsection();
        }
      Declaration declaration;
      declaration.kind = kind;
      prm.enter_subsection("DEM");
      prm.enter_subsection("Sample");
      declaration.sample_type = static_cast<int>(&row_named(sample_types(), prm.get("Type")) - sample_types().data());
      prm.leave_subsection();
      prm.enter_subsection("Loading");
      declaration.loading_test = static_cast<int>(&row_named(lab_tests(), prm.get("Test")) - lab_tests().data());
      prm.leave_subsection();
      prm.leave_subsection();
      return declaration;
    }

    /// Why an entry that some DEM scene may set does not belong to this one.
    std::string foreign_entry_reason(const std::vector<std::string> &path, const Declaration &declaration)
    {
      const std::string kind = scene_kind_names().name(*declaration.kind);
      if (path.front() == "Campaign")
        return "subsection Campaign belongs to scenes of kind campaign or calibration (set Scene = campaign); "
               "this is a `" + kind + "` scene";
      if (path.size() == 3 && path[0] == "DEM" && path[1] == "Sample")
        return "belongs to DEM/Sample/Type = " + variants_with_entry(sample_types(), path[2]) + ", not to this scene's `" +
               sample_types().at(*declaration.sample_type).name + "`";
      if (path.size() == 3 && path[0] == "DEM" && path[1] == "Loading")
        return "belongs to DEM/Loading/Test = " + variants_with_entry(lab_tests(), path[2]) + ", not to this scene's `" +
               lab_tests().at(*declaration.loading_test).name + "`";
      return "does not belong to a `" + kind + "` scene";
    }

    /// Every entry the file sets that its kind and variants do not declare, though another kind or
    /// variant does; entries no DEM scene knows are left to the ParameterHandler's own message.
    void collect_foreign_entries(const std::string &bytes, const Declaration &declaration, Problems &problems)
    {
      ParameterHandler specific, every_kind_and_variant;
      SceneParameters::declare_parameters(specific, declaration);
      SceneParameters::declare_parameters(every_kind_and_variant, Declaration{});
      const auto declared = declared_entries(specific);
      const auto known = declared_entries(every_kind_and_variant);
      bool campaign_reported = false; // a foreign subsection Campaign is named once, not per entry
      for (const ParameterSetting &setting : scan_parameter_settings(bytes))
        if (!declared.count(setting.path) && known.count(setting.path) &&
            !(setting.path.front() == "Campaign" && std::exchange(campaign_reported, true)))
          problems.add(setting.path_text() + " (line " + std::to_string(setting.line) + ")",
                       foreign_entry_reason(setting.path, declaration));
    }
  } // namespace

  SceneParameters read_scene(const std::string &file, const SceneKind kind, const Overrides &overrides,
                             void (*declare_more)(dealii::ParameterHandler &prm))
  {
    SceneParameters scene;
    scene.file = file;
    scene.declare_more = declare_more;
    const std::string bytes = read_scene_file(file);
    scene.file_sha256 = util::sha256_hex(bytes);

    ParameterHandler prm;
    try
    {
      Declaration declaration = declaration_of(bytes, file, kind, overrides);
      declaration.declare_more = declare_more;
      Problems foreign("scene file <" + file + ">");
      collect_foreign_entries(bytes, declaration, foreign);
      foreign.throw_if_any();
      SceneParameters::declare_parameters(prm, declaration);
      parse_parameter_text(prm, bytes, file);
      for (const auto &[path, value] : overrides)
      {
        const std::vector<std::string> parts = split_parameter_path(path);
        for (std::size_t k = 0; k + 1 < parts.size(); ++k)
          prm.enter_subsection(parts[k]);
        try
        {
          prm.set(parts.back(), value);
        }
        catch (const dealii::ExceptionBase &)
        {
          throw std::invalid_argument("the override " + path + " = " + value +
                                      " names no entry, or its value does not match the entry's pattern "
                                      "(`anticrack params` lists them)");
        }
        for (std::size_t k = 0; k + 1 < parts.size(); ++k)
          prm.leave_subsection();
      }
      scene.parse_parameters(prm);
    }
    catch (const dealii::ExceptionBase &e)
    {
      // deal.II's text names the line, the entry and the pattern; drop its stack trace.
      std::ostringstream info;
      e.print_info(info);
      throw InputError("Invalid scene file <" + file + ">:\n" + info.str() +
                       "\n(`anticrack params` lists every entry with its pattern.)");
    }
    catch (const InputError &)
    {
      throw;
    }
    catch (const std::exception &e)
    {
      throw InputError("Invalid scene file <" + file + ">: " + e.what());
    }

    std::ostringstream canonical;
    prm.print_parameters(canonical, ParameterHandler::ShortPRM);
    scene.canonical_parameters = canonical.str();
    scene.parameters_sha256 = util::sha256_hex(scene.canonical_parameters);
    scene.resume_key_sha256 = resume_key(prm);

    Problems problems("scene file <" + file + ">");
    scene.check(problems);
    problems.throw_if_any();
    return scene;
  }

  void require_dem_component(const SceneParameters &scene)
  {
    if (std::find(scene.components.begin(), scene.components.end(), "dem") == scene.components.end())
      throw InputError("Scene <" + scene.file + "> has no runnable component (Components = dem).");
  }

  Declaration scene_declaration(const std::string &file, const SceneKind kind,
                                void (*declare_more)(dealii::ParameterHandler &prm))
  {
    Declaration declaration = scene_declaration(file, kind);
    declaration.declare_more = declare_more;
    return declaration;
  }

  Declaration scene_declaration(const std::string &file, const SceneKind kind)
  {
    try
    {
      return declaration_of(read_scene_file(file), file, kind, {});
    }
    catch (const dealii::ExceptionBase &e)
    {
      std::ostringstream info;
      e.print_info(info);
      throw InputError("Invalid scene file <" + file + ">:\n" + info.str());
    }
  }

  void declare_dem_scene(dealii::ParameterHandler &prm, const Declaration &declaration)
  {
    SceneParameters::declare_parameters(prm, declaration);
  }

  nlohmann::ordered_json scene_info(const SceneParameters &scene)
  {
    nlohmann::ordered_json s;
    s["file"] = scene.file;
    std::error_code error;
    const auto absolute = std::filesystem::absolute(scene.file, error);
    s["absolute_path"] = error ? scene.file : absolute.lexically_normal().string();
    s["file_sha256"] = scene.file_sha256;
    s["parameters_sha256"] = scene.parameters_sha256;
    s["resume_key_sha256"] = scene.resume_key_sha256;
    return s;
  }
} // namespace anticrack::dem
