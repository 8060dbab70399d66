// What a calibration writes (params/calibration.h): the fit data in HDF5 (calibration.h5, layout in
// docs/calibration.md, read by scripts/plot_calibration.py) and the summary.json record. The
// material files the FE solver reads are the hand-off's (coupling/material_handoff.h).
#pragma once

#include "params/calibration.h"

#include <nlohmann/json.hpp>

#include <string>

namespace anticrack::params
{
  /// Writes calibration.h5 to `file` (through `file`.tmp and a rename).
  void write_calibration_data(const Calibration &calibration, const std::string &file);

  /// The calibration's part of summary.json: per microstructure every fitted parameter with its
  /// intervals, goodness of fit, information criteria, flow rule, elastic constants, softening; the
  /// scaling and micro-macro laws.
  nlohmann::ordered_json calibration_summary(const Calibration &calibration);
} // namespace anticrack::params
