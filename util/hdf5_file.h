// The project's one layer over the HDF5 C API, for its tabular files (history.h5, campaign.h5,
// calibration.h5) and the DEM snapshots and checkpoints (dem/io/state_hdf5.h): handles that close
// themselves, groups, datasets and attributes of any native element type (rows x columns, scalar or
// small 1-D attributes), variable-length UTF-8 strings, and the double and string tables with their
// `units` and `description` attributes. Errors throw std::runtime_error naming the file and the
// object path, with HDF5's own reason where it gives one.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace anticrack::hdf5
{
  /// Description of the innermost entry of HDF5's error stack (the stack is then cleared), or "".
  std::string innermost_error();

  /// Throws std::runtime_error("HDF5: cannot <what> (<HDF5's reason>)") when `status` is negative (a
  /// failed call or an invalid id); returns it otherwise.
  herr_t check(herr_t status, const std::string &what);
  hid_t check_id(hid_t id, const std::string &what);

  /// Closes an HDF5 handle when it goes out of scope; throws (as check) if the handle is invalid.
  struct Handle
  {
    using Closer = herr_t (*)(hid_t);
    hid_t id;
    Handle(hid_t i, Closer c, const std::string &what);
    ~Handle();
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
    Handle &operator=(Handle &&) = delete;
    Handle(Handle &&other) noexcept;
    /// Closes now and returns HDF5's status, so that a failure while flushing a file can be
    /// reported (closing twice is a no-op).
    herr_t close_now();

  private:
    Closer closer_;
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
  /// Writes the HDF5 file `file` atomically (util/atomic_file.h): `content(root)` fills a new file
  /// at the temporary path, which is closed (errors reported) and renamed over `file`. `durable`:
  /// flushed to disk before the rename (checkpoints).
  void write_file_atomically(const std::string &file, const std::function<void(const Handle &root)> &content,
                             bool durable = false);
  Handle open_file_read_only(const std::string &file);
  Handle create_group(hid_t parent, const std::string &name);
  Handle open_group(hid_t parent, const std::string &name);
  /// Whether the link `path` (relative to `parent`, may contain '/') exists.
  bool exists(hid_t parent, const std::string &path);
  /// Names of the links in `group`, in name order.
  std::vector<std::string> children(hid_t group);

  // --- strings: written as variable-length UTF-8; read as variable-length strings of the stored
  //     character set (HDF5 does not convert between ASCII and UTF-8)

  /// Variable-length string type of `character_set`.
  Handle string_type(H5T_cset_t character_set = H5T_CSET_UTF8);
  /// Memory type to read strings stored with type `stored` (an attribute's or a dataset's type,
  /// taken over and closed); throws unless they are variable-length strings. `where` names the object.
  Handle string_type_for(hid_t stored, const std::string &where);

  // --- attributes

  bool has_attribute(hid_t object, const std::string &name);
  /// Opens attribute `name` of `object`; throws naming it when it does not exist.
  Handle open_attribute(hid_t object, const std::string &name);
  /// Writes `elements` values of `memory_type` as attribute `name` of `file_type`: a scalar for one
  /// element, a 1-D array otherwise.
  void write_attribute(hid_t object, const std::string &name, hid_t file_type, hid_t memory_type,
                       const void *values, hsize_t elements);
  /// Reads attribute `name` into `values` (`elements` values of `memory_type`); throws unless the
  /// attribute holds exactly that many.
  void read_attribute(hid_t object, const std::string &name, hid_t memory_type, void *values, hsize_t elements);
  void write_string_attribute(hid_t object, const std::string &name, const std::string &value);
  void write_number_attribute(hid_t object, const std::string &name, double value);
  std::string read_string_attribute(hid_t object, const std::string &name);
  /// A numeric attribute, or a string attribute holding a number (campaign.h5 v1 writes labels as
  /// strings).
  double read_number_attribute(hid_t object, const std::string &name);

  // --- datasets

  /// Creates dataset `name` of `file_type` with dimensions `dims` and writes `values` (row-major, of
  /// `memory_type`) unless it is empty; returns the open dataset (for its attributes).
  Handle write_dataset(hid_t group, const std::string &name, hid_t file_type, hid_t memory_type,
                       const std::vector<hsize_t> &dims, const void *values);
  /// Opens dataset `name`; throws naming it when it does not exist.
  Handle open_dataset(hid_t group, const std::string &name);
  /// Opens a table dataset of `columns` columns (rank 1 for one column, rank 2 otherwise) and
  /// `rows` rows (any_rows: any number); throws naming the shape found otherwise. Returns the open
  /// dataset and its row count.
  constexpr std::int64_t any_rows = -1;
  std::pair<Handle, hsize_t> open_table(hid_t group, const std::string &name, hsize_t columns, std::int64_t rows);
  /// Reads a whole dataset into `values` (sized by the caller, of `memory_type`); `where` names it.
  void read_dataset(hid_t dataset, hid_t memory_type, void *values, const std::string &where);

  /// Writes `values` (row-major, `shape` empty = 1-D) as 64-bit floats with units and description.
  void write_doubles(hid_t group, const std::string &name, const std::vector<double> &values,
                     const std::string &units, const std::string &description,
                     const std::vector<hsize_t> &shape = {});
  void write_strings(hid_t group, const std::string &name, const std::vector<std::string> &values,
                     const std::string &description);
  /// Writes `values` as a 1-D variable-length UTF-8 string dataset; returns it open (for its attributes).
  Handle write_string_dataset(hid_t group, const std::string &name, const std::vector<std::string> &values);
  /// Reads a double dataset of any rank (row-major); `shape` receives its dimensions if given.
  std::vector<double> read_doubles(hid_t group, const std::string &name, std::vector<hsize_t> *shape = nullptr);
  std::vector<std::string> read_strings(hid_t group, const std::string &name);
  /// Reads the variable-length strings of an open dataset of `count` elements; `where` names it.
  std::vector<std::string> read_strings(hid_t dataset, hsize_t count, const std::string &where);
} // namespace anticrack::hdf5
