#include "host/io/vtk_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "host/io/atomic_file.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

namespace {

using IoDirTest = pd::testing::TempDirTest;

using VtkWriterTest = IoDirTest;
using PvdSeriesTest = IoDirTest;

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Four particles with values that float32 does not represent exactly, and fragment ids.
pd::FrameData sample_frame() {
  pd::FrameData f;
  f.frame = 3;
  f.step = 1200;
  f.time = 1.0 / 3.0;
  f.position = {{0.1, -0.2, 0.3}, {1e-3, 2.5, -7}, {0, 0, 0}, {-1.1, 1e-7, 3.3}};
  f.velocity = {{1, 2, 3}, {-0.1, 0.2, -0.3}, {0, 0, 0}, {1e3, -1e-3, 0.7}};
  f.damage = {0.f, 0.25f, 1.f, 0.1f};
  f.body = {0, 0, 1, 1};
  f.component = {7, 7, 2, 5};
  return f;
}

// One appended DataArray as declared in the XML.
struct DeclaredArray {
  std::string name, type;
  int components = 1;
  uint64_t offset = 0;
};

// A .vtu split into its XML head, its declared appended arrays and the raw appended block.
struct ParsedVtu {
  std::string xml;
  std::vector<DeclaredArray> arrays;
  std::string appended;  // from the byte after '_' to the end of the file
};

std::map<std::string, std::string> attributes(const std::string& element) {
  std::map<std::string, std::string> out;
  static const std::regex attribute(R"re((\w+)="([^"]*)")re");
  for (std::sregex_iterator it(element.begin(), element.end(), attribute), end; it != end; ++it) {
    out[(*it)[1]] = (*it)[2];
  }
  return out;
}

ParsedVtu parse_vtu(const std::string& file) {
  const std::string marker = "<AppendedData encoding=\"raw\">\n   _";
  size_t at = file.find(marker);
  EXPECT_NE(at, std::string::npos);
  ParsedVtu p{file.substr(0, at), {}, file.substr(at + marker.size())};
  static const std::regex data_array(R"re(<DataArray ([^>]*)/>)re");
  for (std::sregex_iterator it(p.xml.begin(), p.xml.end(), data_array), end; it != end; ++it) {
    auto a = attributes((*it)[1]);
    EXPECT_EQ(a["format"], "appended");
    int components = a.count("NumberOfComponents") ? std::stoi(a["NumberOfComponents"]) : 1;
    p.arrays.push_back({a["Name"], a["type"], components, std::stoull(a["offset"])});
  }
  return p;
}

size_t type_size(const std::string& type) {
  return type == "UInt8" ? 1 : 4;
}

uint64_t size_header(const ParsedVtu& p, uint64_t offset) {
  uint64_t size = 0;
  std::memcpy(&size, p.appended.data() + offset, sizeof size);
  return size;
}

// Each array's offset follows the previous array's UInt64 header and bytes; sizes match the
// point count, and the closing tags follow the last array.
void expect_consistent_appended_data(const ParsedVtu& p, size_t n) {
  uint64_t expected_offset = 0;
  for (const DeclaredArray& a : p.arrays) {
    ASSERT_EQ(a.offset, expected_offset) << a.name;
    ASSERT_LE(a.offset + 8, p.appended.size()) << a.name;
    uint64_t size = size_header(p, a.offset);
    EXPECT_EQ(size, n * a.components * type_size(a.type)) << a.name;
    expected_offset += 8 + size;
  }
  ASSERT_LE(expected_offset, p.appended.size());
  EXPECT_EQ(p.appended.substr(expected_offset), "\n  </AppendedData>\n</VTKFile>\n");
}

template <class T>
std::vector<T> decode(const ParsedVtu& p, const std::string& name) {
  for (const DeclaredArray& a : p.arrays) {
    if (a.name != name) continue;
    std::vector<T> values(size_header(p, a.offset) / sizeof(T));
    std::memcpy(values.data(), p.appended.data() + a.offset + 8, values.size() * sizeof(T));
    return values;
  }
  ADD_FAILURE() << "no array " << name;
  return {};
}

std::vector<std::string> names(const ParsedVtu& p) {
  std::vector<std::string> out;
  for (const DeclaredArray& a : p.arrays) out.push_back(a.name);
  return out;
}

TEST_F(VtkWriterTest, HeaderDeclaresARawAppendedUnstructuredGrid) {
  std::string file_path = path("frame_00003.vtu");
  pd::write_vtu(file_path, sample_frame());
  std::string file = read_all(file_path);
  EXPECT_EQ(file.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                       "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
                       0),
            0u);
  EXPECT_NE(file.find("<Piece NumberOfPoints=\"4\" NumberOfCells=\"4\">"), std::string::npos);

  // TimeValue reads back as the same double.
  std::smatch m;
  std::string xml = parse_vtu(file).xml;
  ASSERT_TRUE(std::regex_search(xml, m, std::regex(R"re(Name="TimeValue"[^>]*>([^<]*)</DataArray>)re")));
  EXPECT_EQ(std::stod(m[1]), 1.0 / 3.0);
}

TEST_F(VtkWriterTest, AppendedOffsetsAndSizesMatch) {
  std::string file_path = path("frame.vtu");
  pd::write_vtu(file_path, sample_frame());
  ParsedVtu p = parse_vtu(read_all(file_path));
  EXPECT_EQ(names(p), (std::vector<std::string>{"velocity", "damage", "body", "id", "component", "Points",
                                                "connectivity", "offsets", "types"}));
  expect_consistent_appended_data(p, 4);
}

TEST_F(VtkWriterTest, ValuesRoundTripAsFloat32) {
  pd::FrameData f = sample_frame();
  std::string file_path = path("frame.vtu");
  pd::write_vtu(file_path, f);
  ParsedVtu p = parse_vtu(read_all(file_path));

  std::vector<float> points = decode<float>(p, "Points"), velocity = decode<float>(p, "velocity");
  ASSERT_EQ(points.size(), 12u);
  ASSERT_EQ(velocity.size(), 12u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(points[3 * i], float(f.position[i].x));
    EXPECT_EQ(points[3 * i + 1], float(f.position[i].y));
    EXPECT_EQ(points[3 * i + 2], float(f.position[i].z));
    EXPECT_EQ(velocity[3 * i], float(f.velocity[i].x));
    EXPECT_EQ(velocity[3 * i + 1], float(f.velocity[i].y));
    EXPECT_EQ(velocity[3 * i + 2], float(f.velocity[i].z));
  }
  EXPECT_EQ(decode<float>(p, "damage"), f.damage);
  EXPECT_EQ(decode<int32_t>(p, "body"), f.body);
  EXPECT_EQ(decode<int32_t>(p, "component"), f.component);
  EXPECT_EQ(decode<int32_t>(p, "id"), (std::vector<int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(decode<int32_t>(p, "connectivity"), (std::vector<int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(decode<int32_t>(p, "offsets"), (std::vector<int32_t>{1, 2, 3, 4}));
  EXPECT_EQ(decode<uint8_t>(p, "types"), (std::vector<uint8_t>(4, 1)));  // VTK_VERTEX
}

TEST_F(VtkWriterTest, EmptyComponentIsLeftOut) {
  pd::FrameData f = sample_frame();
  f.component.clear();
  std::string file_path = path("frame.vtu");
  pd::write_vtu(file_path, f);
  std::string file = read_all(file_path);
  EXPECT_EQ(file.find("component"), std::string::npos);
  ParsedVtu p = parse_vtu(file);
  EXPECT_EQ(p.arrays.size(), 8u);
  expect_consistent_appended_data(p, 4);
}

TEST_F(VtkWriterTest, ZeroParticlesGiveAValidEmptyGrid) {
  pd::FrameData f;
  std::string file_path = path("empty.vtu");
  pd::write_vtu(file_path, f);
  std::string file = read_all(file_path);
  EXPECT_NE(file.find("NumberOfPoints=\"0\" NumberOfCells=\"0\""), std::string::npos);
  expect_consistent_appended_data(parse_vtu(file), 0);
}

TEST_F(VtkWriterTest, InconsistentSizesAreRejectedBeforeWriting) {
  pd::FrameData f = sample_frame();
  f.damage.pop_back();
  EXPECT_THROW(pd::write_vtu(path("bad.vtu"), f), std::invalid_argument);
  f = sample_frame();
  f.component = {1};
  EXPECT_THROW(pd::write_vtu(path("bad.vtu"), f), std::invalid_argument);
  EXPECT_EQ(entry_count(), 0u);
}

TEST_F(VtkWriterTest, MissingDirectoryThrowsIoErrorNamingThePath) {
  std::string target = path("missing/frame_00003.vtu");
  try {
    pd::write_vtu(target, sample_frame());
    ADD_FAILURE() << "no IoError";
  } catch (const pd::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + target + "'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(entry_count(), 0u);
}

// Numbers printed by the VTK reader script, by line label.
std::map<std::string, std::vector<double>> run_vtk_reader(const std::string& script, const std::string& vtu) {
  std::map<std::string, std::vector<double>> out;
  std::string command = "python3 '" + script + "' '" + vtu + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  std::string text;
  char buf[4096];
  while (size_t got = fread(buf, 1, sizeof buf, pipe)) text.append(buf, got);
  pclose(pipe);
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string label;
    words >> label;
    for (double v; words >> v;) out[label].push_back(v);
  }
  EXPECT_FALSE(out.empty()) << text;
  return out;
}

TEST_F(VtkWriterTest, VtkReaderLoadsTheFile) {
  if (std::system("python3 -c 'import vtk' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3 cannot import vtk: the .vtu is not checked with VTK's own reader";
  }
  const char* script_text = R"py(
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(sys.argv[1])
r.Update()
g = r.GetOutput()
print("counts", g.GetNumberOfPoints(), g.GetNumberOfCells(), g.GetCellType(0))
print("time", repr(g.GetFieldData().GetArray("TimeValue").GetValue(0)))
print("Points", *[repr(g.GetPoint(i)[c]) for i in range(g.GetNumberOfPoints()) for c in range(3)])
for name in ["velocity", "damage", "body", "id", "component"]:
    a = g.GetPointData().GetArray(name)
    print(name, *[repr(a.GetComponent(i, c)) for i in range(a.GetNumberOfTuples())
                  for c in range(a.GetNumberOfComponents())])
)py";
  pd::write_file_atomic(path("read.py"), std::string_view(script_text));
  pd::FrameData f = sample_frame();
  pd::write_vtu(path("frame.vtu"), f);

  auto got = run_vtk_reader(path("read.py"), path("frame.vtu"));
  EXPECT_EQ(got["counts"], (std::vector<double>{4, 4, 1}));
  EXPECT_EQ(got["time"], (std::vector<double>{f.time}));
  std::vector<double> points, velocity;
  for (size_t i = 0; i < 4; ++i) {
    for (pd::real v : {f.position[i].x, f.position[i].y, f.position[i].z}) points.push_back(float(v));
    for (pd::real v : {f.velocity[i].x, f.velocity[i].y, f.velocity[i].z}) velocity.push_back(float(v));
  }
  EXPECT_EQ(got["Points"], points);
  EXPECT_EQ(got["velocity"], velocity);
  EXPECT_EQ(got["damage"], std::vector<double>(f.damage.begin(), f.damage.end()));
  EXPECT_EQ(got["body"], std::vector<double>(f.body.begin(), f.body.end()));
  EXPECT_EQ(got["id"], (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(got["component"], std::vector<double>(f.component.begin(), f.component.end()));
}

TEST_F(VtkWriterTest, TrianglesAreReadAsTrianglesWithTheirParts) {
  // Two triangles of parts 3 and 4 sharing an edge.
  pd::TriangleSurface s;
  s.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  s.triangles = {0, 1, 2, 1, 3, 2};
  s.part = {3, 4};
  pd::write_vtu_triangles(path("tri.vtu"), 0.25, s);
  const std::string text = pd::testing::read_all(path("tri.vtu"));
  EXPECT_NE(text.find("NumberOfPoints=\"4\" NumberOfCells=\"2\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"part\""), std::string::npos);
  s.part.pop_back();
  EXPECT_THROW(pd::write_vtu_triangles(path("bad.vtu"), 0, s), std::invalid_argument);
  if (std::system("python3 -c 'import vtk' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3 cannot import vtk: the triangles are not checked with VTK's own reader";
  }
  const char* script_text = R"py(
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(sys.argv[1])
r.Update()
g = r.GetOutput()
print("counts", g.GetNumberOfPoints(), g.GetNumberOfCells(), g.GetCellType(0), g.GetCellType(1))
print("second", *[g.GetCell(1).GetPointId(k) for k in range(3)])
a = g.GetCellData().GetArray("part")
print("part", *[a.GetValue(i) for i in range(a.GetNumberOfTuples())])
)py";
  pd::write_file_atomic(path("read.py"), std::string_view(script_text));
  auto got = run_vtk_reader(path("read.py"), path("tri.vtu"));
  EXPECT_EQ(got["counts"], (std::vector<double>{4, 2, 5, 5}));
  EXPECT_EQ(got["second"], (std::vector<double>{1, 3, 2}));
  EXPECT_EQ(got["part"], (std::vector<double>{3, 4}));
}

TEST_F(PvdSeriesTest, IndexIsRewrittenAfterEachFrame) {
  pd::PvdSeries series(dir_.string(), "run");
  EXPECT_EQ(series.path(), path("run.pvd"));
  EXPECT_FALSE(fs::exists(series.path()));

  const std::string head =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <Collection>\n";
  const std::string tail = "  </Collection>\n</VTKFile>\n";
  const std::string first = "    <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frame_00000.vtu\"/>\n";
  const std::string second =
      "    <DataSet timestep=\"0.125\" group=\"\" part=\"0\" file=\"frame_00001.vtu\"/>\n";

  series.add(0.0, pd::frame_file_name(0, "vtu"));
  EXPECT_EQ(read_all(series.path()), head + first + tail);
  series.add(0.125, pd::frame_file_name(1, "vtu"));
  EXPECT_EQ(read_all(series.path()), head + first + second + tail);
  EXPECT_EQ(series.size(), 2u);
  EXPECT_EQ(entry_count(), 1u);  // no temporaries left
}

TEST_F(PvdSeriesTest, FileNamesAreXmlEscaped) {
  pd::PvdSeries series(dir_.string(), "run");
  series.add(1.5, "a&b\"<c>.vtu");
  EXPECT_NE(read_all(series.path()).find("file=\"a&amp;b&quot;&lt;c&gt;.vtu\""), std::string::npos);
}

TEST_F(PvdSeriesTest, FailedRewriteLeavesTheSeriesUnchanged) {
  pd::PvdSeries series(path("later"), "run");
  EXPECT_THROW(series.add(0.0, "frame_00000.vtu"), pd::IoError);
  EXPECT_EQ(series.size(), 0u);
  fs::create_directory(path("later"));
  series.add(0.5, "frame_00001.vtu");
  std::string index = read_all(series.path());
  EXPECT_EQ(index.find("frame_00000.vtu"), std::string::npos);
  EXPECT_NE(index.find("frame_00001.vtu"), std::string::npos);
}

}  // namespace
