// What the analyses of fem/analysis/ share: the progress log, the time series' writer, the
// .pvd record of the field outputs, the parts of summary.json's results (mesh, energies per width, the beam model of
// fem/closed_forms.h) and the start of both PSTs (gravity equilibrium, self-propagation lead).
// Templates on dim are explicitly instantiated for 2 and 3 in outputs.cpp.
#pragma once

#include "fem/analysis/snowpack_run.h"
#include "fem/closed_forms.h"
#include "fem/model/snowpack_model.h"
#include "util/console.h"
#include "util/enum_table.h"
#include "util/format.h"
#include "util/time_series.h"


#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace anticrack::fem
{
  template <int dim>
  class QuasiStaticSolver;

  /// Progress lines on rank 0 of `communicator` (util/console.h); out == nullptr: quiet.
  ConditionalStream root_log(std::ostream *out, MPI_Comm communicator);

  /// A column of doubles of a time series.
  struct SeriesColumn
  {
    std::string name, unit, description;
  };

  /// A time series of these columns, without rows.
  TimeSeries series_of(const std::vector<SeriesColumn> &columns);

  /// Writes `series` to `file` with its `description` (util/time_series.h) on rank 0.
  void write_on_root(const TimeSeries &series, const std::string &file, const std::string &description,
                     MPI_Comm communicator);

  /// The .pvd record of the field outputs, rewritten after every output by rank 0.
  class FieldRecord
  {
  public:
    FieldRecord(std::string directory, MPI_Comm communicator);

    /// Writes the fields at `time`, unless that time was written last already.
    template <int dim>
    void write(const SnowpackModel<dim> &model, const typename SnowpackModel<dim>::VectorType &u, double time);

    void save(std::ostream &out) const;
    void load(std::istream &in);

  private:
    std::string directory_;
    MPI_Comm communicator_;
    std::vector<std::pair<double, std::string>> entries_;
  };

  /// Width the 2D results are per (1 m, plane strain) or the 3D column width.
  template <int dim>
  double result_width(const SnowpackScene &scene)
  {
    return dim == 2 ? 1. : scene.pst.column_width;
  }

  /// Energies per metre of column width in 3D (2D already counts them per metre).
  template <int dim>
  Energies per_width(Energies e, const SnowpackScene &scene)
  {
    const double width = result_width<dim>(scene);
    for (double *value : {&e.elastic, &e.kinetic, &e.dissipated, &e.viscous, &e.external_work, &e.removed_by_saw})
      *value /= width;
    return e;
  }

  /// The energies of summary.json with the relative error of their balance.
  Json energies_json(const Energies &e);

  /// The mesh of summary.json: dimension, cells, dofs, columns, element length, ranks.
  template <int dim>
  Json mesh_json(const SnowpackModel<dim> &model, MPI_Comm communicator);

  /// The beam on an elastic foundation of fem/closed_forms.h for a snowpack with one slab layer
  /// (several layers have no single E; none is returned then).
  std::optional<closed_forms::SlabOnFoundation> beam_model(const Snowpack &s);

  /// Gaume et al. (2017)'s critical cut length (closed_forms::critical_cut_length_gaume2017) for the
  /// scene's snowpack, evaluated with its own weak layer: G_wl = E/(2(1 + ν)) and τ_p the layer-plane
  /// shear strength of its cohesive Cam-Clay surface (layer_plane_shear_strength) at the slab's
  /// normal stress σ_n = ρ g H cos ψ, laterally confined (k = ν/(1 − ν): a weak layer under a long
  /// slab cannot strain sideways). The independent reference of the saw tests' critical cut; with
  /// its inputs, or a "note" saying why it does not apply (several slab layers, an elastic weak
  /// layer, τ_p <= τ_g).
  Json gaume2017_reference(const Snowpack &s);

  /// The running crack's references (docs/fem.md "Measured"): Heierli (2005)'s flexural-wave speed
  /// and touchdown distance, and the static touchdown of a long cut (Timoshenko and Euler–Bernoulli
  /// slab, closed_forms::steady_state_touchdown_distance), with the weak layer's collapse height;
  /// or a "note" saying why they do not apply (several slab layers, no collapse height).
  Json flexural_wave_reference(const Snowpack &s);

  /// Ends a run that writes no checkpoint (quasi-static PST, energy release rate, load to failure)
  /// between two of its steps when a stop signal (Ctrl-C, SIGTERM; a StopSignals object of the run
  /// installs the handler) has arrived on any rank (collective): throws RunInterrupted naming the
  /// analysis and `where` it stopped; anticrack writes summary.json "interrupted" and exits 130. A
  /// rerun starts over (these runs take minutes, not hours). `before_stopping` (e.g. writing the
  /// series so far) runs on every rank before the throw.
  void stop_if_signalled(const std::string &analysis, const std::string &where, MPI_Comm comm,
                         const std::function<void()> &before_stopping = {});

  /// Throws CollapseUnderGravity when the far-field geostatic state of a collapsing weak layer
  /// (hardening law `collapse`, or no hardening) lies outside its initial yield surface: Eq. 27 of
  /// docs/fem_closed_forms.md at the layer's mid-height against the strength of Eq. 28. The
  /// message names the weak layer's strength entry (or its material file), the strength it would
  /// need and the share of the weight at which it yields. Called before every gravity ramp of a PST.
  void check_weak_layer_carries_the_snowpack(const SnowpackScene &scene);

  /// What the slab does to its weak layer once the layer has softened to its residual (docs/fem.md
  /// "Outcomes"; a collapsing layer only): the laterally confined state under the layers above it
  /// (Eq. 27 of docs/fem_closed_forms.md at mid-height), the strength that holds it (Eq. 28), the
  /// residual strength R p0 against it, the overburden the residual alone carries (the state is
  /// linear in the overburden). Compacting at its residual the layer carries σ_f, the normal stress
  /// of confined flow on the residual surface (confined_flow_normal_stress); where the slab's normal
  /// traction σ_n exceeds it, the densification carries the rest, p_d = σ_n − σ_f, and the layer
  /// closes to the collapse height under the slab h = h_d + H p_d / K_d (h_d = ε_d H the onset of the
  /// densification, K_d its modulus): the height the slab falls, which the closed forms of the
  /// running crack need. Where the residual holds the slab, a crack can run only as the layer's
  /// softening front, without collapse or touchdown, and h = h_d.
  struct CollapseUnderTheSlab
  {
    double overburden = 0;              ///< at the weak layer's mid-height [Pa]
    double strength_to_hold_it = 0;     ///< the p0 that contains the confined state (Eq. 28) [Pa]
    double residual_strength = 0;       ///< R p0 [Pa]
    double carried_by_the_residual = 0; ///< overburden the residual alone carries [Pa]
    double normal_traction = 0;         ///< the slab's layer-normal traction, overburden cos θ [Pa]
    double residual_flow_stress = 0;    ///< σ_f of confined_flow_normal_stress() at R p0 [Pa]
    double densification_pressure = 0;  ///< p_d = max(normal traction − σ_f, 0) [Pa]
    double closure = 0;                 ///< the collapse height under the slab h [m]
    /// The slab keeps compacting the collapsed layer: its normal traction exceeds what the
    /// residual carries in confined flow.
    [[nodiscard]] bool slab_crushes_the_layer() const { return normal_traction > residual_flow_stress; }
  };
  std::optional<CollapseUnderTheSlab> collapse_of_the_weak_layer(const Snowpack &s);
  /// h of collapse_of_the_weak_layer(), or the layer's collapse height (the densification's onset)
  /// where that does not apply: the collapse height of the closed forms (Heierli 2005, the static
  /// touchdown, the band of the critical cut).
  double collapse_height_under_the_slab(const Snowpack &s);
  /// collapse_of_the_weak_layer() as the PST's results write it, with the work of gravity and of
  /// the residual plateau over h (J/m²). Null for another weak layer.
  Json collapse_under_the_slab(const SnowpackScene &scene);

  /// Gravity equilibrium of the uncut column (the start of the quasi-static and the dynamic PST),
  /// after check_weak_layer_carries_the_snowpack().
  template <int dim>
  void gravity_equilibrium(SnowpackModel<dim> &model, QuasiStaticSolver<dim> &solver,
                           typename SnowpackModel<dim>::VectorType &u, ConditionalStream &log);

  /// Where the quasi-static saw stopped (quasi_static_saw()).
  struct QuasiStaticSawEnd
  {
    double cut = 0;                ///< the longest cut in equilibrium [m]
    std::optional<double> lost_at; ///< the cut with which equilibrium was lost (one halved step on) [m]
    bool crack_leads = false;      ///< the crack tip led the saw by the self-propagation lead
    std::string reason;            ///< why it stopped
    double external_work = 0;      ///< gravity's work over the saw steps, f_g · Δu [J (per width in 2D: J/m)]
  };

  /// The quasi-static saw (docs/fem.md "The critical cut"): from the equilibrium u and the model's
  /// cut, cut steps of
  /// `Analysis/Newton/Saw step` (0: one element length), each solved by Newton, a failed step
  /// halved down to 1/64 of it, until equilibrium is lost with the smallest step, the crack tip
  /// leads the saw by the self-propagation lead, or the cut reaches `PST/Cut length`. u and the
  /// model end in the last equilibrium (its cut set). `on_step(cut, fronts, iterations)` after
  /// each converged step. Used by the quasi-static PST and, before it hands over to explicit
  /// dynamics, by the dynamic PST's quasi-static saw.
  template <int dim>
  QuasiStaticSawEnd quasi_static_saw(SnowpackModel<dim> &model, QuasiStaticSolver<dim> &solver,
                                     typename SnowpackModel<dim>::VectorType &u, ConditionalStream &log,
                                     const std::function<void(double, const CrackFronts &, unsigned int)> &on_step);

  /// The crack runs by itself once its tip leads the saw by this distance [m] (both PSTs).
  double self_propagation_lead(const SnowpackScene &scene);

  /// How a dynamic PST ends (docs/fem.md "Outcomes"): End, the crack runs through the column; Arr,
  /// it stops; SF, the slab breaks; no propagation, the cut never grows into a crack that runs by
  /// itself; still running, none of these by the end time.
  enum class PstOutcome
  {
    running,
    end,
    arrest,
    slab_fracture,
    no_propagation
  };

  /// The outcomes' labels in summary.json and the reports: PST practice's End, Arr and SF, as the
  /// field observations write them (CAAML v6 `fracturePropagation`, SnowPilot; Gauthier &
  /// Jamieson 2008), so that a prediction and an observation compare as strings.
  const EnumTable<PstOutcome> &pst_outcome_names();
} // namespace anticrack::fem
