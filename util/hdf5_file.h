// Small RAII helpers around the HDF5 C API for the project's tabular files (history.h5,
// campaign.h5, calibration.h5): handles that close themselves, groups, 1-D/N-D double datasets
// and variable-length UTF-8 string datasets and attributes, each dataset with `units` and
// `description` attributes. Errors throw std::runtime_error naming the file and the object path.
// The DEM library keeps its own reader/writer for snapshots and checkpoints (dem/io/state_hdf5.h).
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

namespace anticrack::hdf5
{
  /// Closes an HDF5 handle when it goes out of scope; throws if the handle is invalid.
  struct Handle
  {
    hid_t id;
    herr_t (*close)(hid_t);
    Handle(hid_t i, herr_t (*c)(hid_t), const std::string &what);
    ~Handle();
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
    Handle(Handle &&other) noexcept;
  };

  /// Turns HDF5's automatic error printing off while it lives (lookups that may fail, readers that
  /// report errors through their own exceptions), and restores it afterwards.
  class QuietErrors
  {
  public:
    QuietErrors()
    {
      H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }
    QuietErrors(const QuietErrors &) = delete;
    QuietErrors &operator=(const QuietErrors &) = delete;

  private:
    H5E_auto2_t function_ = nullptr;
    void *data_ = nullptr;
  };

  /// "file.h5:/group/name" of an open object (for error messages).
  std::string location(hid_t object, const std::string &name = "");

  Handle create_file(const std::string &file);       ///< truncates an existing file
  Handle open_file_read_only(const std::string &file);
  Handle create_group(hid_t parent, const std::string &name);
  Handle open_group(hid_t parent, const std::string &name);
  /// Whether the link `path` (relative to `parent`, may contain '/') exists.
  bool exists(hid_t parent, const std::string &path);
  /// Names of the links in `group`, in name order.
  std::vector<std::string> children(hid_t group);

  void write_string_attribute(hid_t object, const std::string &name, const std::string &value);
  void write_number_attribute(hid_t object, const std::string &name, double value);
  bool has_attribute(hid_t object, const std::string &name);
  std::string read_string_attribute(hid_t object, const std::string &name);
  /// A numeric attribute, or a string attribute holding a number (campaign.h5 v1 writes labels as
  /// strings).
  double read_number_attribute(hid_t object, const std::string &name);

  /// Writes `values` (row-major, `shape` empty = 1-D) as 64-bit floats with units and description.
  void write_doubles(hid_t group, const std::string &name, const std::vector<double> &values,
                     const std::string &units, const std::string &description,
                     const std::vector<hsize_t> &shape = {});
  void write_strings(hid_t group, const std::string &name, const std::vector<std::string> &values,
                     const std::string &description);
  /// Reads a double dataset of any rank (row-major); `shape` receives its dimensions if given.
  std::vector<double> read_doubles(hid_t group, const std::string &name, std::vector<hsize_t> *shape = nullptr);
  std::vector<std::string> read_strings(hid_t group, const std::string &name);
} // namespace anticrack::hdf5
