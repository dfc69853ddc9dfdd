#include "host/io/vtk_writer.h"

#include <charconv>
#include <cstdint>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string_view>

#include "host/io/atomic_file.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the VTK files are declared LittleEndian");

namespace pd {

namespace {

constexpr uint8_t kVtkVertex = 1;    // VTK cell type of a single point
constexpr uint8_t kVtkTriangle = 5;  // and of a triangle

// One array of the appended data: its XML attributes (without offset) and its raw bytes.
struct AppendedArray {
  std::string attributes;
  std::string_view bytes;
};

// One element of the Piece (PointData, Points, Cells) with the arrays it declares.
struct Section {
  std::string open_tag, close_tag;
  std::vector<AppendedArray> arrays;
};

// Shortest text that reads back as the same double.
std::string format_double(double v) {
  char buf[32];
  auto result = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, result.ptr);
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string array_attributes(const char* type, const char* name, int components) {
  std::string a = std::string("type=\"") + type + "\" Name=\"" + name + "\"";
  if (components > 1) a += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  return a;
}

// Per-point arrays derived from the frame that the file needs in another type or layout.
struct DerivedArrays {
  std::vector<float> position, velocity;
  std::vector<int32_t> index;  // 0..n-1: `id`, the connectivity, and the cell offsets (+1)
  std::vector<int32_t> cell_end;
  std::vector<uint8_t> cell_type;

  explicit DerivedArrays(const FrameData& f)
      : position(to_float32(f.position)),
        velocity(to_float32(f.velocity)),
        index(f.size()),
        cell_end(f.size()),
        cell_type(f.size(), kVtkVertex) {
    for (size_t i = 0; i < f.size(); ++i) {
      index[i] = int32_t(i);
      cell_end[i] = int32_t(i + 1);
    }
  }
};

// The Piece's sections in file order; the byte views point into `f` and `d`.
std::vector<Section> piece_sections(const FrameData& f, const DerivedArrays& d) {
  Section point_data{"<PointData Scalars=\"damage\" Vectors=\"velocity\">", "</PointData>", {}};
  point_data.arrays = {{array_attributes("Float32", "velocity", 3), bytes_of(d.velocity)},
                       {array_attributes("Float32", "damage", 1), bytes_of(f.damage)},
                       {array_attributes("Int32", "body", 1), bytes_of(f.body)},
                       {array_attributes("Int32", "id", 1), bytes_of(d.index)}};
  if (!f.component.empty()) {
    point_data.arrays.push_back({array_attributes("Int32", "component", 1), bytes_of(f.component)});
  }
  Section points{"<Points>", "</Points>", {{array_attributes("Float32", "Points", 3), bytes_of(d.position)}}};
  Section cells{"<Cells>",
                "</Cells>",
                {{array_attributes("Int32", "connectivity", 1), bytes_of(d.index)},
                 {array_attributes("Int32", "offsets", 1), bytes_of(d.cell_end)},
                 {array_attributes("UInt8", "types", 1), bytes_of(d.cell_type)}}};
  return {point_data, points, cells};
}

// XML up to and including the '_' that starts the appended data. Each array's offset counts
// from the byte after '_' and skips the UInt64 size header of every array before it.
std::string vtu_header(double time, size_t points, size_t cells, const std::vector<Section>& sections) {
  std::string x =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <FieldData>\n"
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">" +
      format_double(time) +
      "</DataArray>\n"
      "    </FieldData>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) + "\">\n";
  uint64_t offset = 0;
  for (const Section& s : sections) {
    x += "      " + s.open_tag + "\n";
    for (const AppendedArray& a : s.arrays) {
      x += "        <DataArray " + a.attributes + " format=\"appended\" offset=\"" + std::to_string(offset) +
           "\"/>\n";
      offset += sizeof(uint64_t) + a.bytes.size();
    }
    x += "      " + s.close_tag + "\n";
  }
  x += "    </Piece>\n"
       "  </UnstructuredGrid>\n"
       "  <AppendedData encoding=\"raw\">\n"
       "   _";
  return x;
}

// The appended data: for each array a UInt64 byte count followed by the bytes.
void write_appended(std::ostream& out, const std::vector<Section>& sections) {
  for (const Section& s : sections) {
    for (const AppendedArray& a : s.arrays) {
      uint64_t size = a.bytes.size();
      out.write(reinterpret_cast<const char*>(&size), sizeof size);
      out.write(a.bytes.data(), std::streamsize(a.bytes.size()));
    }
  }
}

void write_sections(const std::string& path, const std::string& header,
                    const std::vector<Section>& sections) {
  write_file_atomic(path, [&](std::ostream& out) {
    out << header;
    write_appended(out, sections);
    out << "\n  </AppendedData>\n</VTKFile>\n";
  });
}

}  // namespace

void write_vtu(const std::string& path, const FrameData& f) {
  check_sizes(f);
  if (f.size() > size_t(std::numeric_limits<int32_t>::max())) {
    throw std::invalid_argument("write_vtu: more particles than Int32 ids can number");
  }
  DerivedArrays derived(f);
  std::vector<Section> sections = piece_sections(f, derived);
  write_sections(path, vtu_header(f.time, f.size(), f.size(), sections), sections);
}

void write_vtu_triangles(const std::string& path, double time, const TriangleSurface& s) {
  const size_t points = s.points.size() / 3, cells = s.triangles.size() / 3;
  if (s.points.size() % 3 != 0 || s.triangles.size() % 3 != 0 || s.part.size() != cells)
    throw std::invalid_argument("write_vtu_triangles: arrays of inconsistent lengths");
  std::vector<int32_t> cell_end(cells);
  for (size_t c = 0; c < cells; ++c) cell_end[c] = int32_t(3 * (c + 1));
  const std::vector<uint8_t> cell_type(cells, kVtkTriangle);
  const std::vector<Section> sections = {
      {"<CellData Scalars=\"part\">",
       "</CellData>",
       {{array_attributes("Int32", "part", 1), bytes_of(s.part)}}},
      {"<Points>", "</Points>", {{array_attributes("Float32", "Points", 3), bytes_of(s.points)}}},
      {"<Cells>",
       "</Cells>",
       {{array_attributes("Int32", "connectivity", 1), bytes_of(s.triangles)},
        {array_attributes("Int32", "offsets", 1), bytes_of(cell_end)},
        {array_attributes("UInt8", "types", 1), bytes_of(cell_type)}}}};
  write_sections(path, vtu_header(time, points, cells, sections), sections);
}

PvdSeries::PvdSeries(const std::string& dir, const std::string& name)
    : path_((dir.empty() ? std::string() : dir + "/") + name + ".pvd") {}

void PvdSeries::add(double time, const std::string& file) {
  std::vector<Entry> next = entries_;
  next.push_back({time, file});
  write_file_atomic(path_, render(next));
  entries_ = std::move(next);
}

void PvdSeries::restore(std::vector<Entry> entries) {
  write_file_atomic(path_, render(entries));
  entries_ = std::move(entries);
}

std::string PvdSeries::render(const std::vector<Entry>& entries) {
  std::string x =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <Collection>\n";
  for (const Entry& e : entries) {
    x += "    <DataSet timestep=\"" + format_double(e.time) + "\" group=\"\" part=\"0\" file=\"" +
         xml_escape(e.file) + "\"/>\n";
  }
  x += "  </Collection>\n"
       "</VTKFile>\n";
  return x;
}

}  // namespace pd
