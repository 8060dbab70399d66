#include "app/bench.h"

#include "dem/scene/model.h"
#include "util/input_error.h"
#include "dem/sample/lattice.h"
#include "dem/core/system.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>

namespace anticrack::app
{
  int bench_dem(const BenchOptions &options)
  {
    if (options.lattice < 1 || options.steps < 1 || options.threads < 0)
      throw InputError("bench dem: --lattice and --steps must be positive, --threads >= 0");
    const int threads = dem::apply_thread_count(options.threads);

    const double radius = 1e-3, spacing = 2e-3;
    dem::DemSystem system;
    system.domain.lower = dem::Vec3::Zero();
    system.domain.upper = dem::Vec3::Constant(spacing * options.lattice);
    system.domain.periodic = {true, true, true};

    dem::Material material;
    material.density = 1e4;
    material.contact.law = dem::ContactLaw::linear;
    material.contact.contact_modulus = 1e9;
    material.contact.stiffness_ratio = 3;
    material.contact.friction = 0.5;
    material.bond.enabled = true;
    material.bond.modulus = 1e9;
    material.bond.stiffness_ratio = 3;
    material.bond.radius_multiplier = 1;
    material.bond.tensile_strength = 1e6;
    material.bond.cohesion = 1e6;
    material.bond.friction_angle = 0;
    material.bond.moment_factor = 1;
    system.materials.add(material);

    dem::LatticeSpec spec;
    spec.cells = {options.lattice, options.lattice, options.lattice};
    spec.radius = radius;
    spec.spacing = spacing;
    spec.velocity_amplitude = 1e-6;
    spec.seed = 12345;
    dem::add_simple_cubic_lattice(system, spec);
    system.bond_touching_pairs();

    system.settings.local_damping = 0.7;
    system.settings.time_step = 0;
    system.initialise();
    const dem::Index bonds = system.bonds.count_intact();

    const auto start = std::chrono::steady_clock::now();
    system.run(options.steps);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const auto particles = system.particles.size();
    nlohmann::ordered_json line;
    line["code"] = "anticrack";
    line["particles"] = particles;
    line["bonds"] = bonds;
    line["steps"] = options.steps;
    line["threads"] = threads;
    line["wall_s"] = wall;
    line["particle_steps_per_s"] = wall > 0 ? particles * static_cast<double>(options.steps) / wall : 0.0;
    line["bond_steps_per_s"] = wall > 0 ? bonds * static_cast<double>(options.steps) / wall : 0.0;
    line["dt"] = system.dt;
    line["bonds_broken"] = bonds - system.bonds.count_intact();
    std::cout << line.dump() << std::endl;
    return exit_success;
  }
} // namespace anticrack::app
