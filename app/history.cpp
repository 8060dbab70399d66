#include "app/history.h"

#include "app/hdf5_util.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace anticrack::app
{
  using hdf5::Handle;
  using hdf5::write_string_attribute;

  void History::add_column(const std::string &name, const std::string &unit,
                           const std::string &description, const bool integer)
  {
    if (rows() > 0)
      throw std::logic_error("History: column " + name + " declared after the first row");
    columns_.push_back(Column{name, unit, description, integer, {}});
  }

  void History::append(const std::vector<double> &row)
  {
    if (row.size() != columns_.size())
      throw std::logic_error("History: row has " + std::to_string(row.size()) + " values for " +
                             std::to_string(columns_.size()) + " columns");
    for (std::size_t c = 0; c < row.size(); ++c)
      columns_[c].values.push_back(row[c]);
  }

  void History::truncate_after_step(const double last_step)
  {
    const Column *step = find("step");
    if (step == nullptr)
      return;
    std::size_t keep = 0;
    while (keep < step->values.size() && step->values[keep] <= last_step)
      ++keep;
    for (Column &c : columns_)
      c.values.resize(keep);
  }

  const History::Column *History::find(const std::string &name) const
  {
    for (const Column &c : columns_)
      if (c.name == name)
        return &c;
    return nullptr;
  }

  void History::write(const std::string &file, const std::map<std::string, std::string> &attributes) const
  {
    const std::string temporary = file + ".tmp";
    {
      const Handle f(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                     "create " + temporary);
      for (const auto &[key, value] : attributes)
        write_string_attribute(f.id, key, value);
      const hsize_t n = rows();
      for (const Column &c : columns_)
      {
        const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "create a data space");
        const hid_t file_type = c.integer ? H5T_STD_I64LE : H5T_IEEE_F64LE;
        const Handle set(H5Dcreate2(f.id, c.name.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT,
                                    H5P_DEFAULT),
                         H5Dclose, "create dataset " + c.name + " in " + temporary);
        herr_t status;
        if (c.integer)
        {
          std::vector<std::int64_t> values(c.values.begin(), c.values.end());
          status = H5Dwrite(set.id, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
        }
        else
          status = H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.values.data());
        if (status < 0)
          throw std::runtime_error("HDF5: cannot write dataset " + c.name + " in " + temporary);
        write_string_attribute(set.id, "units", c.unit);
        write_string_attribute(set.id, "description", c.description);
      }
    }
    std::filesystem::rename(temporary, file);
  }

  void History::read(const std::string &file)
  {
    const Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open " + file);
    std::vector<std::vector<double>> values(columns_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c)
    {
      const std::string &name = columns_[c].name;
      if (H5Lexists(f.id, name.c_str(), H5P_DEFAULT) <= 0)
        throw std::runtime_error(file + " has no column " + name);
      const Handle set(H5Dopen2(f.id, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + name + " in " + file);
      const Handle space(H5Dget_space(set.id), H5Sclose, "query " + name);
      hsize_t n = 0;
      if (H5Sget_simple_extent_ndims(space.id) != 1)
        throw std::runtime_error(file + ": " + name + " is not a column");
      H5Sget_simple_extent_dims(space.id, &n, nullptr);
      values[c].resize(n);
      if (n > 0 && H5Dread(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values[c].data()) < 0)
        throw std::runtime_error("HDF5: cannot read " + name + " in " + file);
      if (values[c].size() != values.front().size())
        throw std::runtime_error(file + ": columns have different lengths");
    }
    for (std::size_t c = 0; c < columns_.size(); ++c)
      columns_[c].values = std::move(values[c]);
  }
} // namespace anticrack::app
