#include "util/hdf5_file.h"

#include <stdexcept>

namespace anticrack::hdf5
{
  Handle::Handle(hid_t i, herr_t (*c)(hid_t), const std::string &what) : id(i), close(c)
  {
    if (id < 0)
      throw std::runtime_error("HDF5: cannot " + what);
  }

  Handle::~Handle()
  {
    if (id >= 0)
      close(id);
  }

  Handle::Handle(Handle &&other) noexcept : id(other.id), close(other.close) { other.id = -1; }

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

  namespace
  {
    /// Variable-length UTF-8 strings, the type every string here is written and read as.
    Handle utf8_string_type()
    {
      Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy the string type");
      H5Tset_size(type.id, H5T_VARIABLE);
      H5Tset_cset(type.id, H5T_CSET_UTF8);
      return type;
    }

    Handle open_dataset(hid_t group, const std::string &name)
    {
      if (!exists(group, name))
        throw std::runtime_error("HDF5: " + location(group, name) + " does not exist");
      return Handle(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + location(group, name));
    }
  } // namespace

  Handle create_file(const std::string &file)
  {
    return Handle(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create " + file);
  }

  Handle open_file_read_only(const std::string &file)
  {
    const QuietErrors quiet;
    return Handle(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                  "open " + file + " (missing, or not an HDF5 file)");
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

  void write_string_attribute(hid_t object, const std::string &name, const std::string &value)
  {
    const Handle type = utf8_string_type();
    const Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create a scalar space");
    const Handle attribute(H5Acreate2(object, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT),
                           H5Aclose, "create attribute " + location(object) + "@" + name);
    const char *text = value.c_str();
    if (H5Awrite(attribute.id, type.id, &text) < 0)
      throw std::runtime_error("HDF5: cannot write attribute " + location(object) + "@" + name);
  }

  void write_number_attribute(hid_t object, const std::string &name, double value)
  {
    const Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create a scalar space");
    const Handle attribute(H5Acreate2(object, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT),
                           H5Aclose, "create attribute " + location(object) + "@" + name);
    if (H5Awrite(attribute.id, H5T_NATIVE_DOUBLE, &value) < 0)
      throw std::runtime_error("HDF5: cannot write attribute " + location(object) + "@" + name);
  }

  bool has_attribute(hid_t object, const std::string &name) { return H5Aexists(object, name.c_str()) > 0; }

  std::string read_string_attribute(hid_t object, const std::string &name)
  {
    const std::string where = location(object) + "@" + name;
    if (!has_attribute(object, name))
      throw std::runtime_error("HDF5: attribute " + where + " does not exist");
    const Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + where);
    const Handle stored(H5Aget_type(attribute.id), H5Tclose, "query the type of " + where);
    if (H5Tget_class(stored.id) != H5T_STRING || !H5Tis_variable_str(stored.id))
      throw std::runtime_error("HDF5: attribute " + where + " is not a variable-length string");
    const Handle type = utf8_string_type();
    H5Tset_cset(type.id, H5Tget_cset(stored.id));
    char *text = nullptr;
    if (H5Aread(attribute.id, type.id, &text) < 0)
      throw std::runtime_error("HDF5: cannot read attribute " + where);
    std::string value = text != nullptr ? text : "";
    H5free_memory(text);
    return value;
  }

  double read_number_attribute(hid_t object, const std::string &name)
  {
    const std::string where = location(object) + "@" + name;
    if (!has_attribute(object, name))
      throw std::runtime_error("HDF5: attribute " + where + " does not exist");
    const Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + where);
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
    if (H5Aread(attribute.id, H5T_NATIVE_DOUBLE, &value) < 0)
      throw std::runtime_error("HDF5: cannot read attribute " + where + " as a number");
    return value;
  }

  void write_doubles(hid_t group, const std::string &name, const std::vector<double> &values,
                     const std::string &units, const std::string &description, const std::vector<hsize_t> &shape)
  {
    const std::vector<hsize_t> dims = shape.empty() ? std::vector<hsize_t>{values.size()} : shape;
    const Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                       "create a data space");
    const Handle set(H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Dclose, "create dataset " + location(group, name));
    if (!values.empty() && H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
      throw std::runtime_error("HDF5: cannot write " + location(group, name));
    write_string_attribute(set.id, "units", units);
    write_string_attribute(set.id, "description", description);
  }

  void write_strings(hid_t group, const std::string &name, const std::vector<std::string> &values,
                     const std::string &description)
  {
    const Handle type = utf8_string_type();
    const hsize_t n = values.size();
    const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "create a data space");
    const Handle set(H5Dcreate2(group, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Dclose, "create dataset " + location(group, name));
    std::vector<const char *> pointers;
    for (const auto &v : values)
      pointers.push_back(v.c_str());
    if (n > 0 && H5Dwrite(set.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()) < 0)
      throw std::runtime_error("HDF5: cannot write " + location(group, name));
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
    if (count > 0 && H5Dread(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
      throw std::runtime_error("HDF5: cannot read " + location(group, name) + " as numbers");
    if (shape != nullptr)
      *shape = dims;
    return values;
  }

  std::vector<std::string> read_strings(hid_t group, const std::string &name)
  {
    const Handle set = open_dataset(group, name);
    const Handle stored(H5Dget_type(set.id), H5Tclose, "query the type of " + location(group, name));
    if (H5Tget_class(stored.id) != H5T_STRING || !H5Tis_variable_str(stored.id))
      throw std::runtime_error("HDF5: " + location(group, name) + " is not a variable-length string dataset");
    const Handle type = utf8_string_type();
    H5Tset_cset(type.id, H5Tget_cset(stored.id));
    const Handle space(H5Dget_space(set.id), H5Sclose, "query " + location(group, name));
    const hssize_t n = H5Sget_simple_extent_npoints(space.id);
    std::vector<char *> texts(static_cast<std::size_t>(std::max<hssize_t>(n, 0)), nullptr);
    if (n > 0 && H5Dread(set.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, texts.data()) < 0)
      throw std::runtime_error("HDF5: cannot read " + location(group, name));
    std::vector<std::string> values;
    for (char *text : texts)
    {
      values.emplace_back(text != nullptr ? text : "");
      H5free_memory(text);
    }
    return values;
  }
} // namespace anticrack::hdf5
