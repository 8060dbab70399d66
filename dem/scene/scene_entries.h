// What dem/scene/parameters.cpp and the files of the selections' variants (dem/scene/samples/:
// DEM/Sample/Type; dem/scene/lab_tests/: DEM/Loading/Test) share: declaring and reading entries with deal.II's ParameterHandler, and
// writing values into messages. Only these scene files include deal.II.
#pragma once

#include "dem/common/types.h"
#include "dem/scene/variant.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <array>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace anticrack::dem
{
  namespace Patterns = dealii::Patterns;

  inline constexpr std::array<const char *, 3> axis_name = {"x", "y", "z"};

  /// A vector value in a message: "(x, y, z)".
  std::string vec(const Vec3 &v);

  /// A vector entry: three comma-separated numbers x, y, z (read with get_triple<Vec3>).
  void declare_vector(dealii::ParameterHandler &prm, const std::string &name, const std::string &default_value,
                      const std::string &documentation);

  /// The three comma-separated components of a vector (Vec3) or lattice-size (integer) entry.
  template <class Triple>
  Triple get_triple(const dealii::ParameterHandler &prm, const std::string &name)
  {
    const auto parts = dealii::Utilities::split_string_list(prm.get(name), ',');
    Triple t;
    for (int a = 0; a < 3; ++a)
    {
      if constexpr (std::is_integral_v<std::decay_t<decltype(t[a])>>)
        t[a] = dealii::Utilities::string_to_int(parts.at(a));
      else
        t[a] = dealii::Utilities::string_to_double(parts.at(a));
    }
    return t;
  }

  /// An entry that several variants of one selection read (DEM/Sample/Radius [m]): declared with one
  /// help text by the subsection, named by each variant that reads it.
  struct SharedEntry
  {
    std::string name;
    std::string default_value;
    std::shared_ptr<const dealii::Patterns::PatternBase> pattern;
    std::string documentation;
  };

  /// What a variant's declare_parameters (dem/scene/variant.h) is given: it names its entries in
  /// the order `anticrack params` lists them, its own (entry, vector) and those it shares
  /// (shared). They are declared into a ParameterHandler, or only their names are recorded (which
  /// entries belong to the variant). An entry already declared by an earlier variant (every
  /// variant at once) is skipped.
  class VariantEntries
  {
  public:
    /// Declares into `prm`; `declared` holds the names declared so far.
    VariantEntries(dealii::ParameterHandler &prm, const std::vector<SharedEntry> &shared,
                   std::set<std::string> &declared)
      : prm_(&prm), shared_(&shared), declared_(declared)
    {}
    /// Only records the names into `declared`.
    explicit VariantEntries(std::set<std::string> &declared) : declared_(declared) {}

    void entry(const std::string &name, const std::string &default_value, const dealii::Patterns::PatternBase &pattern,
               const std::string &documentation);
    /// A vector entry (declare_vector).
    void vector(const std::string &name, const std::string &default_value, const std::string &documentation);
    /// An entry of `shared` (the subsection's).
    void shared(const std::string &name);

  private:
    dealii::ParameterHandler *prm_ = nullptr;
    const std::vector<SharedEntry> *shared_ = nullptr;
    std::set<std::string> &declared_;
  };

  /// Declares the selection entry `selection` (its first variant the default) and the entries of
  /// the variant `chosen`, or of every variant if null; `shared`: the entries that several read.
  template <class V>
  void declare_variants(dealii::ParameterHandler &prm, const std::string &selection, const std::vector<V> &variants,
                        const V *chosen, const std::vector<SharedEntry> &shared, const std::string &documentation)
  {
    prm.declare_entry(selection, variants.front().name, Patterns::Selection(names_pattern(variants)), documentation);
    std::set<std::string> declared; // every variant at once: an entry shared by several, once
    VariantEntries entries(prm, shared, declared);
    for (const V &each : variants)
      if (!chosen || chosen == &each)
        each.declare_parameters(entries);
  }
} // namespace anticrack::dem
