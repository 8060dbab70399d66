#include "util/time_series.h"

#include "util/atomic_file.h"
#include "util/hdf5_file.h"

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace anticrack
{
  using hdf5::Handle;
  using hdf5::write_string_attribute;

  TimeSeries::TimeSeries(std::vector<Column> columns) : columns_(std::move(columns)) {}

  void TimeSeries::add_column(const std::string &name, const std::string &unit,
                           const std::string &description, const bool integer)
  {
    if (rows() > 0)
      throw std::logic_error("TimeSeries: column " + name + " declared after the first row");
    columns_.push_back(Column{name, unit, description, integer, {}});
  }

  void TimeSeries::append(const std::vector<double> &row)
  {
    if (row.size() != columns_.size())
      throw std::logic_error("TimeSeries: row has " + std::to_string(row.size()) + " values for " +
                             std::to_string(columns_.size()) + " columns");
    for (std::size_t c = 0; c < row.size(); ++c)
      columns_[c].values.push_back(row[c]);
  }

  void TimeSeries::truncate_after_step(const double last_step)
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

  const TimeSeries::Column *TimeSeries::find(const std::string &name) const
  {
    for (const Column &c : columns_)
      if (c.name == name)
        return &c;
    return nullptr;
  }

  const std::vector<double> &TimeSeries::values(const std::string &name) const
  {
    const Column *c = find(name);
    if (c == nullptr)
      throw std::logic_error("TimeSeries: no column " + name);
    return c->values;
  }

  void TimeSeries::replace_values(const std::function<std::vector<double>(const Column &)> &read_column)
  {
    for (Column &c : columns_)
      c.values = read_column(c);
  }

  void TimeSeries::write(const std::string &file, const std::map<std::string, std::string> &attributes) const
  {
    write_atomically(file, [&](const std::string &temporary) {
      const Handle f = hdf5::create_file(temporary);
      for (const auto &[key, value] : attributes)
        write_string_attribute(f.id, key, value);
      const hsize_t n = rows();
      for (const Column &c : columns_)
      {
        if (!c.integer)
        {
          hdf5::write_doubles(f.id, c.name, c.values, c.unit, c.description);
          continue;
        }
        const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "create a data space");
        const Handle set(H5Dcreate2(f.id, c.name.c_str(), H5T_STD_I64LE, space.id, H5P_DEFAULT, H5P_DEFAULT,
                                    H5P_DEFAULT),
                         H5Dclose, "create dataset " + c.name + " in " + temporary);
        const std::vector<std::int64_t> values(c.values.begin(), c.values.end());
        if (H5Dwrite(set.id, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
          throw std::runtime_error("HDF5: cannot write dataset " + c.name + " in " + temporary);
        write_string_attribute(set.id, "units", c.unit);
        write_string_attribute(set.id, "description", c.description);
      }
    });
  }

  void TimeSeries::read(const std::string &file)
  {
    const Handle f = hdf5::open_file_read_only(file);
    std::vector<std::vector<double>> values(columns_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c)
    {
      std::vector<hsize_t> shape;
      values[c] = hdf5::read_doubles(f.id, columns_[c].name, &shape);
      if (shape.size() != 1)
        throw std::runtime_error(file + ": " + columns_[c].name + " is not a column");
      if (values[c].size() != values.front().size())
        throw std::runtime_error(file + ": columns have different lengths");
    }
    for (std::size_t c = 0; c < columns_.size(); ++c)
      columns_[c].values = std::move(values[c]);
  }
} // namespace anticrack
