// What a calibration writes (params/calibration.h): the fit data in HDF5 (calibration.h5, layout in
// docs/calibration.md, read by scripts/plot_calibration.py), one material file per microstructure
// (a `.prm` subsection `Material` that the FE solver reads, with the campaign's hashes and the
// confidence intervals) and the summary.json record.
#pragma once

#include "params/calibration.h"

#include <nlohmann/json.hpp>

#include <string>

namespace anticrack::params
{
  /// Writes calibration.h5 to `file` (through `file`.tmp and a rename).
  void write_calibration_data(const Calibration &calibration, const std::string &file);

  /// The material file of microstructure `m`: the (p, q)-plane Cam-Clay surface, elasticity, density,
  /// collapse softening, with provenance and the intervals. `tool_version` goes into the header.
  std::string material_file_text(const Calibration &calibration, std::size_t m, const std::string &tool_version);

  /// The calibration's part of summary.json: per microstructure every fitted parameter with its
  /// intervals, goodness of fit, information criteria, flow rule, elastic constants, softening; the
  /// scaling and micro-macro laws.
  nlohmann::ordered_json calibration_summary(const Calibration &calibration);
} // namespace anticrack::params
