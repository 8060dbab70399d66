#include "dem/scene/scene_entries.h"

#include "dem/scene/parameters.h"

#include <stdexcept>

namespace anticrack::dem
{
  std::string vec(const Vec3 &v) { return "(" + format_vector(v) + ")"; }

  namespace
  {
    const Patterns::List vector_pattern(Patterns::Double(), 3, 3);
    const std::string vector_note = " Three comma-separated numbers x, y, z.";
  }

  void declare_vector(dealii::ParameterHandler &prm, const std::string &name, const std::string &default_value,
                      const std::string &documentation)
  {
    prm.declare_entry(name, default_value, vector_pattern, documentation + vector_note);
  }

  void VariantEntries::entry(const std::string &name, const std::string &default_value,
                             const Patterns::PatternBase &pattern, const std::string &documentation)
  {
    if (declared_.insert(name).second && prm_)
      prm_->declare_entry(name, default_value, pattern, documentation);
  }

  void VariantEntries::vector(const std::string &name, const std::string &default_value,
                              const std::string &documentation)
  {
    entry(name, default_value, vector_pattern, documentation + vector_note);
  }

  void VariantEntries::shared(const std::string &name)
  {
    if (!prm_)
    {
      declared_.insert(name);
      return;
    }
    for (const SharedEntry &e : *shared_)
      if (e.name == name)
        return entry(e.name, e.default_value, *e.pattern, e.documentation);
    throw std::logic_error("VariantEntries: `" + name + "` is no shared entry of this subsection");
  }

  bool Variant::has_entry(const std::string &entry) const
  {
    std::set<std::string> declared;
    VariantEntries entries(declared);
    declare_parameters(entries);
    return declared.count(entry) > 0;
  }
} // namespace anticrack::dem
