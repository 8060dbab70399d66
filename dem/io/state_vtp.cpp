// ParaView output: particles and bonds as VTK XML PolyData (ASCII) and a .pvd time series
// (formats in io_vtp.h). Numbers are written with std::to_chars, the shortest decimal form that
// reads back as the same double, independent of the locale. One generic DataArray writer serves
// every array and derives the VTK type from the element type.
#include "dem/io/state_vtp.h"

#include "util/atomic_file.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <locale>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <tuple>
#include <type_traits>
#include <utility>

namespace anticrack::dem::io
{
  namespace
  {
    /// Writes one number in its shortest round-trip decimal form.
    template <class Number>
    void put_number(std::ostream &out, Number value)
    {
      char text[32];
      const auto end = std::to_chars(text, text + sizeof(text), value).ptr;
      out.write(text, end - text);
    }

    /// <DataArray> with one element (scalar or Vec3) per line. The VTK type follows from the scalar
    /// type: Float64 (double, Vec3), Int32 (int), Int64 (Index), UInt8 (std::uint8_t).
    template <class T>
    void put_data_array(std::ostream &out, std::string_view name, const std::vector<T> &values)
    {
      constexpr bool is_vec3 = std::is_same_v<T, Vec3>;
      using Scalar = std::conditional_t<is_vec3, double, T>;
      static_assert(std::is_arithmetic_v<Scalar>, "no VTK type for this element type");
      out << "<DataArray type=\""
          << (std::is_floating_point_v<Scalar> ? "Float" : std::is_signed_v<Scalar> ? "Int" : "UInt")
          << 8 * sizeof(Scalar) << "\" Name=\"" << name << "\" NumberOfComponents=\"" << (is_vec3 ? 3 : 1)
          << "\" format=\"ascii\">\n";
      for (const T &value : values)
      {
        if constexpr (is_vec3)
        {
          for (int a = 0; a < 3; ++a)
          {
            put_number(out, value[a]);
            out.put(a < 2 ? ' ' : '\n');
          }
        }
        else
        {
          put_number(out, +value); // + writes a UInt8 as a number, not a character
          out.put('\n');
        }
      }
      out << "</DataArray>\n";
    }

    /// Cells given by their point lists (connectivity) and end offsets, as <Verts> or <Lines>.
    void put_cells(std::ostream &out, std::string_view section, const std::vector<Index> &connectivity,
                   Index points_per_cell)
    {
      std::vector<Index> offsets(connectivity.size() / points_per_cell);
      for (std::size_t c = 0; c < offsets.size(); ++c)
        offsets[c] = static_cast<Index>(c + 1) * points_per_cell;
      out << '<' << section << ">\n";
      put_data_array(out, "connectivity", connectivity);
      put_data_array(out, "offsets", offsets);
      out << "</" << section << ">\n";
    }

    void put_header(std::ostream &out, std::size_t points, std::size_t verts, std::size_t lines)
    {
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
          << "<Piece NumberOfPoints=\"" << points << "\" NumberOfVerts=\"" << verts << "\" NumberOfLines=\""
          << lines << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
    }

    void put_footer(std::ostream &out) { out << "</Piece>\n</PolyData>\n</VTKFile>\n"; }

    void put_points(std::ostream &out, const std::vector<Vec3> &points)
    {
      out << "<Points>\n";
      put_data_array(out, "position", points);
      out << "</Points>\n";
    }

    std::string xml_escape(std::string_view text)
    {
      std::string escaped;
      for (char c : text)
        switch (c)
        {
          case '&': escaped += "&amp;"; break;
          case '<': escaped += "&lt;"; break;
          case '>': escaped += "&gt;"; break;
          case '"': escaped += "&quot;"; break;
          case '\'': escaped += "&apos;"; break;
          default: escaped += c;
        }
      return escaped;
    }

    std::string xml_unescape(std::string_view text)
    {
      static constexpr std::pair<std::string_view, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
      std::string plain;
      for (std::size_t k = 0; k < text.size();)
      {
        bool replaced = false;
        for (const auto &[entity, character] : entities)
          if (text.substr(k, entity.size()) == entity)
          {
            plain += character;
            k += entity.size();
            replaced = true;
            break;
          }
        if (!replaced)
          plain += text[k++];
      }
      return plain;
    }

    /// Reads attribute `name="..."` of `element` into `value`; false when it is absent.
    bool attribute_value(std::string_view element, std::string_view name, std::string &value)
    {
      const std::string key = " " + std::string(name) + "=\"";
      const std::size_t begin = element.find(key);
      if (begin == std::string_view::npos)
        return false;
      const std::size_t first = begin + key.size();
      const std::size_t end = element.find('"', first);
      if (end == std::string_view::npos)
        return false;
      value = xml_unescape(element.substr(first, end - first));
      return true;
    }
  } // namespace

  void write_particles_vtp(const std::string &file, const DemSystem &system)
  {
    const ParticleStore &p = system.particles;
    std::vector<Index> connectivity(p.size());
    for (Index k = 0; k < p.size(); ++k)
      connectivity[k] = k;
    write_text_atomically(file, [&](std::ostream &out) {
      put_header(out, p.size(), p.size(), 0);
      out << "<PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
      put_data_array(out, "radius", p.radius);
      put_data_array(out, "velocity", p.velocity);
      put_data_array(out, "angular_velocity", p.angular_velocity);
      put_data_array(out, "force", p.force);
      put_data_array(out, "material_id", p.material_id);
      put_data_array(out, "group_id", p.group_id);
      put_data_array(out, "clump_id", p.clump_id);
      out << "</PointData>\n";
      put_points(out, p.position);
      put_cells(out, "Verts", connectivity, 1);
      put_footer(out);
    });
  }

  void write_bonds_vtp(const std::string &file, const DemSystem &system)
  {
    const BondList &bonds = system.bonds;
    const Index bond_count = bonds.size();
    std::vector<Vec3> points = system.particles.position;
    std::vector<Index> connectivity;
    connectivity.reserve(2 * bond_count);
    std::vector<std::uint8_t> state(bond_count);
    std::vector<double> shear_force(bond_count), sigma(bond_count), tau(bond_count);
    for (Index b = 0; b < bond_count; ++b)
    {
      // Periodic bonds end at the image x_j + shift next to x_i, not at x_j across the box.
      Index end = bonds.j[b];
      if (bonds.shift[b] != Vec3::Zero())
      {
        end = static_cast<Index>(points.size());
        points.push_back(system.particles.position[bonds.j[b]] + bonds.shift[b]);
      }
      connectivity.push_back(bonds.i[b]);
      connectivity.push_back(end);
      state[b] = static_cast<std::uint8_t>(bonds.state[b]);
      shear_force[b] = bonds.shear_force[b].norm();
      std::tie(sigma[b], tau[b]) = bonds.rim_stresses(b);
    }
    write_text_atomically(file, [&](std::ostream &out) {
      put_header(out, points.size(), 0, bond_count);
      out << "<CellData Scalars=\"state\">\n";
      put_data_array(out, "state", state);
      put_data_array(out, "normal_force", bonds.normal_force);
      put_data_array(out, "shear_force", shear_force);
      put_data_array(out, "sigma", sigma);
      put_data_array(out, "tau", tau);
      out << "</CellData>\n";
      put_points(out, points);
      put_cells(out, "Lines", connectivity, 2);
      put_footer(out);
    });
  }

  PvdCollection::PvdCollection(std::string pvd_file) : pvd_file_(std::move(pvd_file)) {}

  void PvdCollection::add(double time, const std::string &dataset_file)
  {
    namespace fs = std::filesystem;
    const fs::path directory = fs::absolute(pvd_file_).lexically_normal().parent_path();
    const fs::path relative = fs::absolute(dataset_file).lexically_normal().lexically_relative(directory);
    const std::string stored =
      relative.empty() ? fs::absolute(dataset_file).string() : relative.generic_string();
    entries_.push_back({time, stored});
    write();
  }

  void PvdCollection::load_existing(double up_to_time)
  {
    std::ifstream in(pvd_file_);
    if (!in)
      return;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    entries_.clear();
    for (std::size_t begin = text.find("<DataSet"); begin != std::string::npos;
         begin = text.find("<DataSet", begin + 1))
    {
      const std::string_view element = std::string_view(text).substr(begin, text.find('>', begin) - begin);
      std::string time_text, file;
      double time = 0;
      if (!attribute_value(element, "timestep", time_text) || !attribute_value(element, "file", file) ||
          std::from_chars(time_text.data(), time_text.data() + time_text.size(), time).ec != std::errc())
        throw std::runtime_error("anticrack::dem::io: " + pvd_file_ + ": unreadable DataSet entry \"" +
                                 std::string(element) + "\"");
      if (time <= up_to_time)
        entries_.push_back({time, file});
    }
    write();
  }

  void PvdCollection::write() const
  {
    write_text_atomically(pvd_file_, [&](std::ostream &out) {
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
      for (const Entry &entry : entries_)
      {
        out << "<DataSet timestep=\"";
        put_number(out, entry.time);
        out << "\" group=\"\" part=\"0\" file=\"" << xml_escape(entry.file) << "\"/>\n";
      }
      out << "</Collection>\n</VTKFile>\n";
    });
  }
} // namespace anticrack::dem::io
