// Binary checkpoint streams of the FE solver: plain values and vectors of trivially copyable types,
// each vector with its length, so that a stream that does not match what reads it is found (a
// checkpoint of another scene, mesh or number of ranks) instead of being read out of step.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace anticrack::fem::checkpoint
{
  /// A checkpoint that cannot be read back as what wrote it.
  class Mismatch : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  template <typename T>
  void write(std::ostream &out, const T &value)
  {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char *>(&value), sizeof(T));
  }

  template <typename T>
  void read(std::istream &in, T &value)
  {
    static_assert(std::is_trivially_copyable_v<T>);
    if (!in.read(reinterpret_cast<char *>(&value), sizeof(T)))
      throw Mismatch("the checkpoint ends early");
  }

  template <typename T>
  void write_vector(std::ostream &out, const std::vector<T> &values)
  {
    write(out, std::uint64_t(values.size()));
    out.write(reinterpret_cast<const char *>(values.data()), sizeof(T) * values.size());
  }

  /// Reads a vector written by write_vector(); `expected_size` (if not -1) must match.
  template <typename T>
  void read_vector(std::istream &in, std::vector<T> &values, std::int64_t expected_size, const std::string &what)
  {
    std::uint64_t size = 0;
    read(in, size);
    if (expected_size >= 0 && size != std::uint64_t(expected_size))
      throw Mismatch(what + ": the checkpoint holds " + std::to_string(size) + " values, this model " +
                     std::to_string(expected_size));
    values.resize(size);
    if (!in.read(reinterpret_cast<char *>(values.data()), sizeof(T) * size))
      throw Mismatch(what + ": the checkpoint ends early");
  }
} // namespace anticrack::fem::checkpoint
