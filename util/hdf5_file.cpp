#include "util/hdf5_file.h"

#include "util/atomic_file.h"

#include <algorithm>
#include <stdexcept>

namespace anticrack::hdf5
{
  std::string innermost_error()
  {
    std::string description;
    H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned depth, const H5E_error2_t *error, void *data) -> herr_t {
        if (depth == 0 && error->desc != nullptr)
          *static_cast<std::string *>(data) = error->desc;
        return 0;
      },
      &description);
    H5Eclear2(H5E_DEFAULT);
    return description;
  }

  namespace
  {
    [[noreturn]] void fail(const std::string &what)
    {
      const std::string reason = innermost_error();
      throw std::runtime_error("HDF5: cannot " + what + (reason.empty() ? "" : " (" + reason + ")"));
    }
  } // namespace

  herr_t check(const herr_t status, const std::string &what)
  {
    if (status < 0)
      fail(what);
    return status;
  }

  hid_t check_id(const hid_t id, const std::string &what)
  {
    if (id < 0)
      fail(what);
    return id;
  }

  Handle::Handle(hid_t i, Closer c, const std::string &what) : id(check_id(i, what)), closer_(c) {}

  Handle::~Handle() { close_now(); }

  Handle::Handle(Handle &&other) noexcept : id(other.id), closer_(other.closer_) { other.id = -1; }

  herr_t Handle::close_now()
  {
    if (id < 0)
      return 0;
    const hid_t open = id;
    id = -1;
    return closer_(open);
  }

  std::string location(hid_t object, const std::string &name)
  {
    char file[1024] = "?", path[1024] = "?";
    H5Fget_name(object, file, sizeof file);
    H5Iget_name(object, path, sizeof path);
    std::string where = std::string(file) + ":" + path;
    if (!name.empty())
      where += (where.back() == '/' ? "" : "/") + name;
    return where;
  }

  Handle create_file(const std::string &file)
  {
    return Handle(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create " + file);
  }

  void write_file_atomically(const std::string &file, const std::function<void(const Handle &root)> &content,
                             const bool durable)
  {
    const QuietErrors quiet; // errors are reported through our exceptions
    write_atomically(
      file,
      [&](const std::string &temporary) {
        Handle root = create_file(temporary);
        content(root);
        check(root.close_now(), "close file " + temporary);
      },
      durable);
  }

  Handle open_file_read_only(const std::string &file)
  {
    const QuietErrors quiet;
    return Handle(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                  "open file " + file + " (missing, or not an HDF5 file)");
  }

  Handle create_group(hid_t parent, const std::string &name)
  {
    return Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                  "create group " + location(parent, name));
  }

  Handle open_group(hid_t parent, const std::string &name)
  {
    if (!exists(parent, name))
      throw std::runtime_error("HDF5: group " + location(parent, name) + " does not exist");
    return Handle(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), H5Gclose, "open group " + location(parent, name));
  }

  bool exists(hid_t parent, const std::string &path)
  {
    // H5Lexists needs every intermediate link to exist, so walk the path one link at a time.
    const QuietErrors quiet;
    std::string prefix;
    std::size_t start = 0;
    while (start <= path.size())
    {
      const std::size_t slash = path.find('/', start);
      prefix += (prefix.empty() ? "" : "/") + path.substr(start, slash - start);
      if (H5Lexists(parent, prefix.c_str(), H5P_DEFAULT) <= 0)
        return false;
      if (slash == std::string::npos)
        break;
      start = slash + 1;
    }
    return true;
  }

  std::vector<std::string> children(hid_t group)
  {
    H5G_info_t info;
    if (H5Gget_info(group, &info) < 0)
      throw std::runtime_error("HDF5: cannot list " + location(group));
    std::vector<std::string> names;
    for (hsize_t k = 0; k < info.nlinks; ++k)
    {
      const ssize_t length = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
      std::string name(static_cast<std::size_t>(length), '\0');
      H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1, H5P_DEFAULT);
      names.push_back(name);
    }
    return names;
  }

  // ---------------------------------------------------------------------------------------------
  // Strings

  Handle string_type(const H5T_cset_t character_set)
  {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy the string type");
    check(H5Tset_size(type.id, H5T_VARIABLE), "make the string type variable-length");
    check(H5Tset_cset(type.id, character_set), "set the character set of the string type");
    return type;
  }

  Handle string_type_for(const hid_t stored, const std::string &where)
  {
    const Handle stored_type(stored, H5Tclose, "query the type of " + where);
    if (H5Tget_class(stored_type.id) != H5T_STRING || H5Tis_variable_str(stored_type.id) <= 0)
      throw std::runtime_error("HDF5: " + where + " is not made of variable-length strings");
    return string_type(H5Tget_cset(stored_type.id));
  }

  // ---------------------------------------------------------------------------------------------
  // Attributes

  bool has_attribute(hid_t object, const std::string &name) { return H5Aexists(object, name.c_str()) > 0; }

  Handle open_attribute(hid_t object, const std::string &name)
  {
    const std::string where = location(object) + "@" + name;
    if (!has_attribute(object, name))
      throw std::runtime_error("HDF5: attribute " + where + " does not exist");
    return Handle(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + where);
  }

  void write_attribute(hid_t object, const std::string &name, hid_t file_type, hid_t memory_type,
                       const void *values, hsize_t elements)
  {
    const std::string where = location(object) + "@" + name;
    const Handle space(elements == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &elements, nullptr), H5Sclose,
                       "create the data space of attribute " + where);
    const Handle attribute(H5Acreate2(object, name.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT),
                           H5Aclose, "create attribute " + where);
    check(H5Awrite(attribute.id, memory_type, values), "write attribute " + where);
  }

  void read_attribute(hid_t object, const std::string &name, hid_t memory_type, void *values, hsize_t elements)
  {
    const std::string where = location(object) + "@" + name;
    const Handle attribute = open_attribute(object, name);
    const Handle space(H5Aget_space(attribute.id), H5Sclose, "query the size of attribute " + where);
    const hssize_t stored = H5Sget_simple_extent_npoints(space.id);
    if (stored != static_cast<hssize_t>(elements))
      throw std::runtime_error("HDF5: attribute " + where + " has " + std::to_string(stored) + " elements, expected " +
                               std::to_string(elements));
    check(H5Aread(attribute.id, memory_type, values), "read attribute " + where);
  }

  void write_string_attribute(hid_t object, const std::string &name, const std::string &value)
  {
    const Handle type = string_type();
    const char *text = value.c_str();
    write_attribute(object, name, type.id, type.id, &text, 1);
  }

  void write_number_attribute(hid_t object, const std::string &name, double value)
  {
    write_attribute(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, 1);
  }

  std::string read_string_attribute(hid_t object, const std::string &name)
  {
    const std::string where = location(object) + "@" + name;
    const Handle attribute = open_attribute(object, name);
    const Handle type = string_type_for(H5Aget_type(attribute.id), "attribute " + where);
    char *text = nullptr;
    check(H5Aread(attribute.id, type.id, &text), "read attribute " + where);
    std::string value = text != nullptr ? text : "";
    H5free_memory(text);
    return value;
  }

  double read_number_attribute(hid_t object, const std::string &name)
  {
    const std::string where = location(object) + "@" + name;
    const Handle attribute = open_attribute(object, name);
    const Handle stored(H5Aget_type(attribute.id), H5Tclose, "query the type of " + where);
    if (H5Tget_class(stored.id) == H5T_STRING)
    {
      const std::string text = read_string_attribute(object, name);
      std::size_t used = 0;
      try
      {
        const double value = std::stod(text, &used);
        if (used == text.size())
          return value;
      }
      catch (const std::exception &)
      {
      }
      throw std::runtime_error("HDF5: attribute " + where + " = \"" + text + "\" is not a number");
    }
    double value = 0;
    check(H5Aread(attribute.id, H5T_NATIVE_DOUBLE, &value), "read attribute " + where + " as a number");
    return value;
  }

  // ---------------------------------------------------------------------------------------------
  // Datasets

  Handle write_dataset(hid_t group, const std::string &name, hid_t file_type, hid_t memory_type,
                       const std::vector<hsize_t> &dims, const void *values)
  {
    const std::string where = location(group, name);
    const Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                       "create the data space of " + where);
    Handle set(H5Dcreate2(group, name.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose, "create dataset " + where);
    hsize_t count = 1;
    for (const hsize_t d : dims)
      count *= d;
    if (count > 0)
      check(H5Dwrite(set.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "write " + where);
    return set;
  }

  Handle open_dataset(hid_t group, const std::string &name)
  {
    if (!exists(group, name))
      throw std::runtime_error("HDF5: " + location(group, name) + " does not exist");
    return Handle(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + location(group, name));
  }

  std::pair<Handle, hsize_t> open_table(hid_t group, const std::string &name, hsize_t columns, std::int64_t rows)
  {
    const std::string where = location(group, name);
    Handle set = open_dataset(group, name);
    const Handle space(H5Dget_space(set.id), H5Sclose, "query the shape of " + where);
    const int rank = check(H5Sget_simple_extent_ndims(space.id), "query the shape of " + where);
    hsize_t dims[2] = {0, 1};
    if (rank == 1 || rank == 2)
      check(H5Sget_simple_extent_dims(space.id, dims, nullptr), "query the shape of " + where);
    const bool rows_match = rows == any_rows || dims[0] == static_cast<hsize_t>(rows);
    if (rank != (columns == 1 ? 1 : 2) || dims[1] != columns || !rows_match)
    {
      std::string found = "rank " + std::to_string(rank);
      if (rank == 1 || rank == 2)
        found = "shape (" + std::to_string(dims[0]) + (rank == 2 ? ", " + std::to_string(dims[1]) : "") + ")";
      const std::string rows_text = rows == any_rows ? "n" : std::to_string(rows);
      throw std::runtime_error("HDF5: " + where + " has " + found + ", expected shape (" + rows_text +
                               (columns == 1 ? "" : ", " + std::to_string(columns)) + ")");
    }
    return {std::move(set), dims[0]};
  }

  void read_dataset(hid_t dataset, hid_t memory_type, void *values, const std::string &where)
  {
    check(H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "read " + where);
  }

  void write_doubles(hid_t group, const std::string &name, const std::vector<double> &values,
                     const std::string &units, const std::string &description, const std::vector<hsize_t> &shape)
  {
    const std::vector<hsize_t> dims = shape.empty() ? std::vector<hsize_t>{values.size()} : shape;
    const Handle set = write_dataset(group, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims, values.data());
    write_string_attribute(set.id, "units", units);
    write_string_attribute(set.id, "description", description);
  }

  Handle write_string_dataset(hid_t group, const std::string &name, const std::vector<std::string> &values)
  {
    const Handle type = string_type();
    std::vector<const char *> pointers;
    for (const auto &v : values)
      pointers.push_back(v.c_str());
    return write_dataset(group, name, type.id, type.id, {values.size()}, pointers.data());
  }

  void write_strings(hid_t group, const std::string &name, const std::vector<std::string> &values,
                     const std::string &description)
  {
    const Handle set = write_string_dataset(group, name, values);
    write_string_attribute(set.id, "description", description);
  }

  std::vector<double> read_doubles(hid_t group, const std::string &name, std::vector<hsize_t> *shape)
  {
    const Handle set = open_dataset(group, name);
    const Handle space(H5Dget_space(set.id), H5Sclose, "query " + location(group, name));
    const int rank = H5Sget_simple_extent_ndims(space.id);
    std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
    H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
    hsize_t count = 1;
    for (const hsize_t d : dims)
      count *= d;
    std::vector<double> values(count);
    if (count > 0)
      read_dataset(set.id, H5T_NATIVE_DOUBLE, values.data(), location(group, name) + " as numbers");
    if (shape != nullptr)
      *shape = dims;
    return values;
  }

  std::vector<std::string> read_strings(hid_t dataset, hsize_t count, const std::string &where)
  {
    const Handle type = string_type_for(H5Dget_type(dataset), where);
    std::vector<char *> texts(count, nullptr);
    if (count > 0)
      read_dataset(dataset, type.id, texts.data(), where);
    std::vector<std::string> values;
    for (char *text : texts)
    {
      values.emplace_back(text != nullptr ? text : "");
      H5free_memory(text);
    }
    return values;
  }

  std::vector<std::string> read_strings(hid_t group, const std::string &name)
  {
    const Handle set = open_dataset(group, name);
    const Handle space(H5Dget_space(set.id), H5Sclose, "query " + location(group, name));
    const hssize_t n = H5Sget_simple_extent_npoints(space.id);
    return read_strings(set.id, static_cast<hsize_t>(std::max<hssize_t>(n, 0)), location(group, name));
  }
} // namespace anticrack::hdf5
