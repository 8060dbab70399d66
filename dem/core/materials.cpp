#include "dem/core/materials.h"

#include <algorithm>

namespace anticrack::dem
{
  int MaterialTable::add(const Material &m)
  {
    materials_.push_back(m);
    rebuild_pairs();
    return size() - 1;
  }

  void MaterialTable::set_pair_contact(int a, int b, const ContactParameters &p)
  {
    if (a < 0 || b < 0 || a >= size() || b >= size())
      throw SetupError("set_pair_contact: material id out of range");
    pair_contact_[a * size() + b] = p;
    pair_contact_[b * size() + a] = p;
    pair_set_[a * size() + b] = pair_set_[b * size() + a] = 1;
  }

  void MaterialTable::rebuild_pairs()
  {
    // Keep explicitly set pairs, fill the rest from the material with the smaller id.
    const int n = size();
    std::vector<ContactParameters> pairs(n * n);
    std::vector<char> set(n * n, 0);
    const int old_n = n - 1;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
      {
        if (a < old_n && b < old_n && pair_set_[a * old_n + b])
        {
          pairs[a * n + b] = pair_contact_[a * old_n + b];
          set[a * n + b] = 1;
        }
        else
          pairs[a * n + b] = materials_[std::min(a, b)].contact;
      }
    pair_contact_ = std::move(pairs);
    pair_set_ = std::move(set);
  }
} // namespace anticrack::dem
