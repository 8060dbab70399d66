// The time series of a run (the DEM's history.h5, the FE's series.h5 and energy_release_rate.h5): a
// table of named columns, one HDF5 dataset per column with `units` and `description` attributes,
// rows appended as the run goes. The whole table is kept in memory (a few hundred bytes per row)
// and rewritten atomically at every checkpoint and at the end; a resumed run reads it back (from
// the file, read(), or from its own checkpoint, replace_values()) and drops the rows recorded after
// its checkpoint.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace anticrack
{
  class TimeSeries
  {
  public:
    struct Column
    {
      std::string name;
      std::string unit;
      std::string description;
      bool integer = false; ///< stored as int64 (values are kept as doubles in memory)
      std::vector<double> values;
    };

    TimeSeries() = default;

    /// A table of given columns, which may differ in length (e.g. values at cuts and at their
    /// midpoints); append() needs equal lengths.
    explicit TimeSeries(std::vector<Column> columns);

    /// Declares a column; all columns must be declared before the first row.
    void add_column(const std::string &name, const std::string &unit, const std::string &description,
                    bool integer = false);

    /// Appends one row, values in the order the columns were declared.
    void append(const std::vector<double> &row);

    /// Drops the rows whose `step` column exceeds `last_step`.
    void truncate_after_step(double last_step);

    [[nodiscard]] std::size_t rows() const { return columns_.empty() ? 0 : columns_.front().values.size(); }
    [[nodiscard]] const std::vector<Column> &columns() const { return columns_; }
    [[nodiscard]] const Column *find(const std::string &name) const;
    /// The values of column `name`; throws std::logic_error if there is none.
    [[nodiscard]] const std::vector<double> &values(const std::string &name) const;

    /// Replaces the values of every column, in declaration order, by what `read_column` returns for
    /// it (e.g. read back from a checkpoint stream that holds columns() in that order).
    void replace_values(const std::function<std::vector<double>(const Column &)> &read_column);

    /// Writes `file` (via file.tmp and a rename); `attributes` become string attributes of "/".
    void write(const std::string &file, const std::map<std::string, std::string> &attributes) const;

    /// Replaces the values of the declared columns by those stored in `file`; throws
    /// std::runtime_error if a declared column is missing or the lengths differ.
    void read(const std::string &file);

  private:
    std::vector<Column> columns_;
  };
} // namespace anticrack
