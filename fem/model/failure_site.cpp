#include "fem/model/failure_site.h"

#include <deal.II/base/mpi.h>

namespace anticrack::fem
{
  Json failure_site(const std::string &description)
  {
    return Json{{"description", description}};
  }

  Json first_failure_site_on_any_rank(const Json &local_site, MPI_Comm communicator)
  {
    // Sites are small; every rank sends its own (or "") and all take the first.
    const std::string local = local_site.is_null() ? std::string() : local_site.dump();
    for (const std::string &from_rank : dealii::Utilities::MPI::all_gather(communicator, local))
      if (!from_rank.empty())
        return Json::parse(from_rank);
    return nullptr;
  }

  Json failure_site_of(const ReturnMappingError &e)
  {
    if (const auto *model = dynamic_cast<const ModelReturnMappingError *>(&e))
      return model->where();
    return failure_site(e.what());
  }
} // namespace anticrack::fem
