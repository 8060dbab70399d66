// Small RAII helpers around the HDF5 C API for the application's own files (history.h5,
// campaign.h5): a handle that closes itself and string attributes. The DEM library has its own
// reader/writer for snapshots and checkpoints (dem/io_hdf5.h).
#pragma once

#include <hdf5.h>

#include <stdexcept>
#include <string>

namespace anticrack::app::hdf5
{
  /// Closes an HDF5 handle when it goes out of scope; throws if the handle is invalid.
  struct Handle
  {
    hid_t id;
    herr_t (*close)(hid_t);
    Handle(hid_t i, herr_t (*c)(hid_t), const std::string &what) : id(i), close(c)
    {
      if (id < 0)
        throw std::runtime_error("HDF5: cannot " + what);
    }
    ~Handle()
    {
      if (id >= 0)
        close(id);
    }
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
  };

  inline void write_string_attribute(hid_t object, const std::string &name, const std::string &value)
  {
    const Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy the string type");
    H5Tset_size(type.id, H5T_VARIABLE);
    H5Tset_cset(type.id, H5T_CSET_UTF8);
    const Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create a scalar space");
    const Handle attribute(H5Acreate2(object, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT),
                           H5Aclose, "create attribute " + name);
    const char *text = value.c_str();
    if (H5Awrite(attribute.id, type.id, &text) < 0)
      throw std::runtime_error("HDF5: cannot write attribute " + name);
  }
} // namespace anticrack::app::hdf5
