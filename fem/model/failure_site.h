// Where a numerical failure happened in a snowpack model, for summary.json's failure.where (docs/fem.md
// "Failures and interruptions"): a one-line description for the log, and what is known of the place:
// the layer, the cell (deal.II CellId) and its centre, or the node, the quadrature point or the
// displacement component, and the rank that found it. Every rank must report the same site, so the
// model gathers the first one found on any rank (first_failure_site_on_any_rank()).
#pragma once

#include "fem/material/cohesive_cam_clay.h"
#include "util/run_summary.h"

#include <mpi.h>

#include <string>

namespace anticrack::fem
{
  /// A site with only its description (a failure whose place the model does not know, e.g. the
  /// linear solver's).
  Json failure_site(const std::string &description);

  /// The first non-null `local_site` of the ranks, in rank order, on every rank (null if none).
  /// Collective.
  Json first_failure_site_on_any_rank(const Json &local_site, MPI_Comm communicator);

  /// A return mapping failed in the model: the material's message with the site in `where()`
  /// (layer, cell, cell centre, quadrature point, rank), the same on every rank.
  class ModelReturnMappingError : public ReturnMappingError
  {
  public:
    explicit ModelReturnMappingError(Json where)
      : ReturnMappingError(where.value("description", std::string("the return mapping failed")))
      , where_(std::move(where))
    {}
    const Json &where() const { return where_; }

  private:
    Json where_;
  };

  /// The site of a caught return-mapping failure: the model's, or the bare message of another.
  Json failure_site_of(const ReturnMappingError &e);
} // namespace anticrack::fem
