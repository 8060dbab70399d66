#include "fem/analysis/outputs.h"
#include "util/atomic_file.h"

#include "fem/model/checkpoint.h"
#include "fem/solver/quasi_static.h"
#include "util/stop_signals.h"

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace anticrack::fem
{
  using namespace dealii;

  ConditionalStream root_log(std::ostream *out, MPI_Comm communicator)
  {
    return ConditionalStream(out, Utilities::MPI::this_mpi_process(communicator) == 0);
  }

  TimeSeries series_of(const std::vector<SeriesColumn> &columns)
  {
    TimeSeries series;
    for (const SeriesColumn &c : columns)
      series.add_column(c.name, c.unit, c.description);
    return series;
  }

  void write_on_root(const TimeSeries &series, const std::string &file, const std::string &description,
                     MPI_Comm communicator)
  {
    if (Utilities::MPI::this_mpi_process(communicator) == 0)
      series.write(file, {{"description", description}});
  }

  FieldRecord::FieldRecord(std::string directory, MPI_Comm communicator)
    : directory_(std::move(directory)), communicator_(communicator)
  {
    if (Utilities::MPI::this_mpi_process(communicator) == 0)
      std::filesystem::create_directories(directory_);
    MPI_Barrier(communicator);
  }

  template <int dim>
  void FieldRecord::write(const SnowpackModel<dim> &model, const typename SnowpackModel<dim>::VectorType &u,
                          double time)
  {
    if (!entries_.empty() && entries_.back().first == time)
      return;
    const std::string pvtu = model.write_fields(u, directory_, "fields", entries_.size());
    entries_.emplace_back(time, pvtu);
    if (Utilities::MPI::this_mpi_process(communicator_) == 0)
    {
      write_text_atomically(directory_ + "/fields.pvd", [&](std::ostream &out) { DataOutBase::write_pvd_record(out, entries_); });
    }
  }

  void FieldRecord::save(std::ostream &out) const
  {
    checkpoint::write(out, std::uint64_t(entries_.size()));
    for (const auto &[time, name] : entries_)
    {
      checkpoint::write(out, time);
      checkpoint::write_vector(out, std::vector<char>(name.begin(), name.end()));
    }
  }

  void FieldRecord::load(std::istream &in)
  {
    std::uint64_t n = 0;
    checkpoint::read(in, n);
    entries_.clear();
    for (std::uint64_t k = 0; k < n; ++k)
    {
      double time = 0;
      std::vector<char> name;
      checkpoint::read(in, time);
      checkpoint::read_vector(in, name, -1, "field record");
      entries_.emplace_back(time, std::string(name.begin(), name.end()));
    }
  }

  Json energies_json(const Energies &e)
  {
    Json j;
    j["elastic_J"] = e.elastic;
    j["kinetic_J"] = e.kinetic;
    j["dissipated_plastic_J"] = e.dissipated;
    j["dissipated_viscous_J"] = e.viscous;
    j["removed_by_saw_J"] = e.removed_by_saw;
    j["external_work_J"] = e.external_work;
    const double stored = e.elastic + e.kinetic + e.dissipated + e.viscous + e.removed_by_saw;
    j["balance_error_relative"] =
      std::abs(e.external_work - stored) / std::max({std::abs(e.external_work), std::abs(e.elastic), 1e-300});
    return j;
  }

  template <int dim>
  Json mesh_json(const SnowpackModel<dim> &model, MPI_Comm communicator)
  {
    Json j;
    j["dimension"] = dim;
    j["cells"] = model.n_cells();
    j["dofs"] = model.n_dofs();
    j["columns"] = model.n_columns();
    j["element_length_m"] = model.scene().pst.column_length / model.n_columns();
    j["weak_layer_elements"] = model.scene().mesh.weak_layer_elements;
    j["ranks"] = Utilities::MPI::n_mpi_processes(communicator);
    return j;
  }

  std::optional<closed_forms::SlabOnFoundation> beam_model(const Snowpack &s)
  {
    if (s.slab_layers.size() != 1)
      return std::nullopt;
    closed_forms::SlabOnFoundation beam;
    const ContinuumMaterial &slab = s.slab_layers[0].material;
    beam.slab_thickness = s.slab_layers[0].thickness;
    beam.slab_youngs_modulus = slab.youngs_modulus;
    beam.slab_poisson_ratio = slab.poisson_ratio;
    beam.slab_density = slab.density;
    beam.weak_layer_thickness = s.weak_layer.thickness;
    beam.weak_layer_youngs_modulus = s.weak_layer.material.youngs_modulus;
    beam.weak_layer_poisson_ratio = s.weak_layer.material.poisson_ratio;
    beam.gravity = s.gravity;
    beam.slope_angle = s.slope_angle;
    return beam;
  }

  namespace
  {
    /// The band the saw tests' critical cut must lie in (docs/fem.md): the coupled stress and energy
    /// criterion of finite fracture mechanics (Rosendahl & Weißgraeber 2020) on the beam on an elastic
    /// foundation, with the two extreme energies the tip's advance can need.
    ///  - lower: the stress criterion alone, the first tip yield (no energy is needed before it);
    ///  - upper: the stress criterion and the energy of a full collapse, G(a) = σ_c h_c. A weak-layer
    ///    element whose stress never exceeds its confined compressive strength σ_c and whose faces
    ///    approach by at most the collapse height h_c dissipates no more than σ_c h_c per unit area,
    ///    with no credit for the slab's fall: once the elastic slab alone releases that much, the tip
    ///    must advance.
    Json critical_cut_band(const closed_forms::SlabOnFoundation &beam, const Json &first_tip_yield,
                           const double k, const double p0, const CamClayParameters &surface,
                           const double collapse_height)
    {
      Json band;
      band["what"] = "coupled stress and energy criterion on the beam on an elastic foundation: lower = the first tip "
                     "yield (stress alone), upper = max(first tip yield, the cut where G(a) = sigma_c h_c, the work "
                     "of a full collapse at the confined compressive strength)";
      if (!first_tip_yield.is_number() || !(collapse_height > 0))
      {
        band["note"] = first_tip_yield.is_number() ? "the weak layer has no collapse height: no energy side"
                                                   : "the first tip yield was not evaluated";
        return band;
      }
      const double sigma_c = layer_plane_compressive_strength(k, p0, surface);
      const double full_collapse = sigma_c * collapse_height;
      band["confined_compressive_strength_Pa"] = sigma_c;
      band["collapse_height_m"] = collapse_height;
      band["full_collapse_energy_J_per_m2"] = full_collapse;
      band["lower_m"] = first_tip_yield;
      try
      {
        const double energy_side = closed_forms::cut_length_for_fracture_energy(beam, full_collapse);
        band["energy_cut_length_m"] = energy_side;
        band["upper_m"] = std::max(energy_side, first_tip_yield.get<double>());
      }
      catch (const std::exception &e)
      {
        band["upper_m"] = nullptr;
        band["note"] = std::string("no energy side: ") + e.what();
      }
      return band;
    }
  } // namespace

  Json gaume2017_reference(const Snowpack &s)
  {
    Json j;
    j["what"] = "Gaume et al. (2017) closed form with this snowpack's slab and weak layer; tau_p = the weak layer's "
                "cohesive Cam-Clay shear strength at sigma_n, laterally confined";
    const auto beam = beam_model(s);
    const char *not_applicable = !beam ? "several slab layers have no single E: not evaluated"
                                 : s.weak_layer.model != Layer::Model::cohesive_cam_clay
                                   ? "the weak layer is elastic: it has no shear strength"
                                   : nullptr;
    if (not_applicable)
    {
      j["note"] = not_applicable;
      return j;
    }
    const ContinuumMaterial &m = s.weak_layer.material;
    CamClayParameters surface;
    surface.M = m.M;
    surface.beta = m.beta;
    const double sigma_n = closed_forms::normal_load(*beam), tau_g = closed_forms::tangential_load(*beam);
    const double k = m.poisson_ratio / (1 - m.poisson_ratio);
    const double tau_p = layer_plane_shear_strength(sigma_n, k, m.p0, surface);
    j["normal_stress_Pa"] = sigma_n;
    j["slope_parallel_stress_Pa"] = tau_g;
    j["lateral_stress_ratio"] = k;
    j["weak_layer_shear_strength_Pa"] = std::isfinite(tau_p) ? Json(tau_p) : Json(nullptr);
    j["shear_lag_length_m"] = closed_forms::shear_lag_length(*beam);
    try
    {
      j["critical_cut_length_m"] = closed_forms::critical_cut_length_gaume2017(*beam, tau_p);
    }
    catch (const std::exception &e)
    {
      j["critical_cut_length_m"] = nullptr;
      j["note"] = std::string("not evaluated: ") + e.what();
    }
    // The same beam and surface with the tip's normal traction rising too (compression failure):
    // the cut at which the tip first yields.
    try
    {
      j["first_tip_yield_cut_length_m"] = closed_forms::first_tip_yield_cut_length(
        *beam, [&](const double sigma) { return layer_plane_shear_strength(sigma, k, m.p0, surface); });
    }
    catch (const std::exception &e)
    {
      j["first_tip_yield_cut_length_m"] = nullptr;
      j["first_tip_yield_note"] = std::string("not evaluated: ") + e.what();
    }
    j["band"] = critical_cut_band(*beam, j["first_tip_yield_cut_length_m"], k, m.p0, surface,
                                  collapse_height_under_the_slab(s));
    return j;
  }

  void stop_if_signalled(const std::string &analysis, const std::string &where, MPI_Comm comm,
                         const std::function<void()> &before_stopping)
  {
    if (!Utilities::MPI::logical_or(StopSignals::requested(), comm))
      return;
    if (before_stopping)
      before_stopping();
    throw RunInterrupted(analysis + " stopped by a signal at " + where +
                           "; this analysis writes no checkpoint: run it again to redo it");
  }

  Json flexural_wave_reference(const Snowpack &s)
  {
    Json j;
    j["what"] = "closed forms for the running crack with this snowpack's slab and weak layer: Heierli (2005)'s "
                "solitary flexural wave (Euler-Bernoulli slab, E not E'), and the static touchdown of a long cut "
                "(the steady state of Rosendahl et al. 2025's slab-touchdown model, rigid collapsed layer)";
    const auto beam = beam_model(s);
    const double collapse_height = collapse_height_under_the_slab(s);
    if (!beam || !(collapse_height > 0))
    {
      j["note"] = !beam ? "several slab layers have no single E: not evaluated"
                        : "the weak layer has no collapse height: not evaluated";
      return j;
    }
    j["collapse_height_m"] = collapse_height;
    j["heierli2005_speed_m_per_s"] = closed_forms::flexural_wave_speed_heierli2005(
      beam->slab_youngs_modulus, beam->slab_thickness, beam->slab_density, collapse_height, beam->gravity);
    j["heierli2005_touchdown_distance_m"] = closed_forms::touchdown_distance_heierli2005(
      beam->slab_youngs_modulus, beam->slab_thickness, beam->slab_density, collapse_height, beam->gravity);
    for (const auto &[key, shear] : {std::pair{"steady_state_touchdown_distance_m", closed_forms::SlabShear::timoshenko},
                                     std::pair{"steady_state_touchdown_distance_euler_bernoulli_m",
                                               closed_forms::SlabShear::euler_bernoulli}})
      try
      {
        j[key] = closed_forms::steady_state_touchdown_distance(*beam, collapse_height, shear);
      }
      catch (const std::exception &e)
      {
        j[key] = nullptr;
        j["note"] = std::string("not evaluated: ") + e.what();
      }
    return j;
  }

  void check_weak_layer_carries_the_snowpack(const SnowpackScene &scene)
  {
    const Snowpack &s = scene.snowpack;
    const Layer &weak = s.weak_layer;
    const ContinuumMaterial &m = weak.material;
    // Under the `signed` law compaction hardens: a layer at yield carries more, it does not collapse.
    if (weak.model != Layer::Model::cohesive_cam_clay || (m.hardening_law != "collapse" && m.hardening_factor > 0))
      return;
    // the band's rows deform as one and carry the load at the layer's mid-height
    const double overburden = s.slab_weight_per_area() + m.density * weak.thickness / 2 * s.gravity;
    const auto [p, q] = closed_forms::confined_layer_invariants(overburden, s.slope_angle, m.poisson_ratio);
    const double needed = closed_forms::strength_to_contain(p, q, m.beta, m.M);
    if (m.p0 >= needed)
      return;
    const std::string entry = weak.material_file.empty()
                                ? "Snowpack/Weak layer/Compressive strength p0 [Pa]"
                                : "Material/Compressive strength p0 [Pa] of " + weak.material_file;
    std::ostringstream message;
    message << "the weak layer cannot carry the snowpack: under the weight of the layers above it (" << format_number(overburden, 4)
            << " Pa at its mid-height, slope " << format_number(s.slope_angle * 180 / M_PI, 3)
            << " deg) its confined state p = " << format_number(p, 4) << " Pa, q = " << format_number(q, 4)
            << " Pa reaches the yield surface at " << format_number(100 * m.p0 / needed, 3)
            << " % of the weight, and a collapsing layer then collapses under gravity alone, before any saw cut "
               "(docs/fem_closed_forms.md Eq. 28). "
            << entry << " = " << format_number(m.p0, 4) << " must exceed " << format_number(needed, 4)
            << " Pa for this slab, slope, beta, M and Poisson's ratio (or make the slab lighter).";
    throw CollapseUnderGravity(message.str(),
                               {{"what", "weak layer collapse under gravity"},
                                {"where", {{"layer", "weak layer"}, {"state", "far field (laterally confined)"}}},
                                {"when", {{"phase", "before the gravity ramp"}, {"load_factor", m.p0 / needed}}},
                                {"overburden_Pa", overburden},
                                {"mean_pressure_Pa", p},
                                {"von_mises_stress_Pa", q},
                                {"strength_needed_Pa", needed},
                                {"strength_Pa", m.p0},
                                {"entry", entry}});
  }

  std::optional<CollapseUnderTheSlab> collapse_of_the_weak_layer(const Snowpack &s)
  {
    const Layer &weak = s.weak_layer;
    const ContinuumMaterial &m = weak.material;
    if (weak.model != Layer::Model::cohesive_cam_clay || m.hardening_law != "collapse" ||
        !(m.residual_strength_ratio > 0))
      return std::nullopt;
    CollapseUnderTheSlab c;
    // the band's rows deform as one and carry the load at the layer's mid-height (as the check
    // before the gravity ramp)
    c.overburden = s.slab_weight_per_area() + m.density * weak.thickness / 2 * s.gravity;
    const auto [p, q] = closed_forms::confined_layer_invariants(c.overburden, s.slope_angle, m.poisson_ratio);
    c.strength_to_hold_it = closed_forms::strength_to_contain(p, q, m.beta, m.M);
    c.residual_strength = m.residual_strength_ratio * m.p0;
    // The confined state scales with the overburden, and so does the strength that holds it.
    c.carried_by_the_residual = c.overburden * c.residual_strength / c.strength_to_hold_it;
    // Compacting at its residual, the layer carries the normal stress of confined flow on the
    // floor's surface; the densification's pressure p_d = K_d (ε − ε_d) (it adds to every normal
    // stress) carries the rest of the slab's normal traction: the layer closes by H ε_d to the
    // onset and by H p_d / K_d more. (On a slope the slab's shear goes to the collapsed layer's
    // friction, not into this balance.)
    CamClayParameters surface;
    surface.M = m.M;
    surface.beta = m.beta;
    c.normal_traction = c.overburden * std::cos(s.slope_angle);
    c.residual_flow_stress = confined_flow_normal_stress(c.residual_strength, surface);
    c.densification_pressure = std::max(0.0, c.normal_traction - c.residual_flow_stress);
    c.closure = weak.collapse_height;
    if (weak.collapse_height > 0 && weak.densification_modulus > 0)
      c.closure += weak.thickness * c.densification_pressure / weak.densification_modulus;
    return c;
  }

  double collapse_height_under_the_slab(const Snowpack &s)
  {
    const auto c = collapse_of_the_weak_layer(s);
    return c ? c->closure : s.weak_layer.collapse_height;
  }

  Json collapse_under_the_slab(const SnowpackScene &scene)
  {
    const auto c = collapse_of_the_weak_layer(scene.snowpack);
    if (!c)
      return nullptr;
    const double onset = scene.snowpack.weak_layer.collapse_height;
    return {{"overburden_Pa", c->overburden},
            {"strength_to_hold_it_Pa", c->strength_to_hold_it},
            {"residual_strength_Pa", c->residual_strength},
            {"residual_strength_ratio", scene.snowpack.weak_layer.material.residual_strength_ratio},
            {"overburden_the_residual_carries_Pa", c->carried_by_the_residual},
            {"normal_traction_Pa", c->normal_traction},
            {"residual_confined_flow_stress_Pa", c->residual_flow_stress},
            {"slab_crushes_the_collapsed_layer", c->slab_crushes_the_layer()},
            {"densification_onset_m", onset},
            {"densification_pressure_Pa", c->densification_pressure},
            {"collapse_height_m", c->closure},
            {"gravity_work_over_the_collapse_J_per_m2", c->overburden * c->closure},
            {"residual_plateau_work_J_per_m2", std::min(c->carried_by_the_residual, c->overburden) * c->closure}};
  }

  template <int dim>
  void gravity_equilibrium(SnowpackModel<dim> &model, QuasiStaticSolver<dim> &solver,
                           typename SnowpackModel<dim>::VectorType &u, ConditionalStream &log)
  {
    check_weak_layer_carries_the_snowpack(model.scene());
    const auto start = std::chrono::steady_clock::now();
    try
    {
      solver.apply_gravity(u, model.scene().analysis.gravity_steps, [&](double load, const NewtonResult &r) {
        log.line("[fem] gravity ", format_number(100 * load, 3), " %: ", r.iterations, " Newton iterations, |r|/|f| = ",
                 format_number(r.relative_residual, 2));
      });
    }
    catch (const GravityRampFailure &e)
    {
      // Newton's reason names the cell of a failed return mapping, or the linear solver.
      throw NumericalFailure(std::string("gravity equilibrium: ") + e.what(),
                             {{"what", "gravity ramp"},
                              {"where", e.site.is_null() ? failure_site(e.what()) : e.site},
                              {"when", {{"phase", "gravity equilibrium"}, {"load_factor", e.load_factor}}}});
    }
    log.line("[fem] gravity equilibrium in ",
             format_number(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 3), " s");
  }

  double self_propagation_lead(const SnowpackScene &scene)
  {
    return scene.analysis.self_propagation_lead > 0 ? scene.analysis.self_propagation_lead
                                                    : scene.snowpack.slab_thickness();
  }

  template void FieldRecord::write<2>(const SnowpackModel<2> &, const SnowpackModel<2>::VectorType &, double);
  template void FieldRecord::write<3>(const SnowpackModel<3> &, const SnowpackModel<3>::VectorType &, double);
  template Json mesh_json<2>(const SnowpackModel<2> &, MPI_Comm);
  template Json mesh_json<3>(const SnowpackModel<3> &, MPI_Comm);
  template void gravity_equilibrium<2>(SnowpackModel<2> &, QuasiStaticSolver<2> &, SnowpackModel<2>::VectorType &,
                                       ConditionalStream &);
  template void gravity_equilibrium<3>(SnowpackModel<3> &, QuasiStaticSolver<3> &, SnowpackModel<3>::VectorType &,
                                       ConditionalStream &);
  const EnumTable<PstOutcome> &pst_outcome_names()
  {
    static const EnumTable<PstOutcome> names{{"End", PstOutcome::end},
                                             {"Arr", PstOutcome::arrest},
                                             {"SF", PstOutcome::slab_fracture},
                                             {"no propagation", PstOutcome::no_propagation},
                                             {"still running", PstOutcome::running}};
    return names;
  }
} // namespace anticrack::fem
