// `nsf export`: every format read back with a minimal reader written here, against the frame
// as RunReader sees it; collection files; bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "io/colormap.h"
#include "io/h5_util.h"
#include "io/run_reader.h"
#include "synthetic_run.h"

namespace fs = std::filesystem;
using nsf::Mat3;
using nsf::Vec3;
using nsf::testing::run_cli;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

template <typename T>
T get_le(const std::string& buf, size_t& pos) {
  T v;
  std::memcpy(&v, buf.data() + pos, sizeof(T));
  pos += sizeof(T);
  return v;
}

template <typename T>
T get_be(const std::string& buf, size_t& pos) {
  char b[sizeof(T)];
  for (size_t i = 0; i < sizeof(T); ++i) b[i] = buf[pos + sizeof(T) - 1 - i];
  pos += sizeof(T);
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

std::string next_line(const std::string& buf, size_t& pos) {
  const size_t end = buf.find('\n', pos);
  std::string line = buf.substr(pos, end - pos);
  pos = end + 1;
  return line;
}

// Bytes of the PLY type names that both meshio (7.0's binary reader) and VTK read; nsf must
// declare no other (meshio rejects "ushort", which nsf wrote before, and "float64").
size_t ply_type_bytes(const std::string& type) {
  const std::map<std::string, size_t> sized = {{"int8", 1},  {"uint8", 1},  {"uint16", 2},
                                               {"int32", 4}, {"uint32", 4}, {"float32", 4},
                                               {"double", 8}};
  const auto it = sized.find(type);
  return it == sized.end() ? 0 : it->second;
}

// A PLY file as property name -> one value per vertex (as double). Checks that the header
// declares only sized type names and that they add up to the file's size.
std::map<std::string, std::vector<double>> read_ply(const fs::path& path) {
  const std::string buf = slurp(path);
  size_t pos = 0;
  EXPECT_EQ(next_line(buf, pos), "ply");
  EXPECT_EQ(next_line(buf, pos), "format binary_little_endian 1.0");
  size_t n = 0;
  std::vector<std::pair<std::string, std::string>> props;  // type, name
  for (std::string line; (line = next_line(buf, pos)) != "end_header";) {
    std::istringstream ls(line);
    std::string word, type, name;
    ls >> word;
    if (word == "element") {
      ls >> name >> n;
      EXPECT_EQ(name, "vertex");
    } else if (word == "property") {
      ls >> type >> name;
      props.emplace_back(type, name);
    }
  }
  size_t vertex_bytes = 0;
  for (const auto& [type, name] : props) {
    EXPECT_NE(ply_type_bytes(type), 0u) << "PLY type '" << type << "' of " << name;
    vertex_bytes += ply_type_bytes(type);
  }
  EXPECT_EQ(buf.size() - pos, n * vertex_bytes) << "the header's types do not match the data";
  std::map<std::string, std::vector<double>> out;
  if (buf.size() - pos != n * vertex_bytes) return out;
  for (size_t i = 0; i < n; ++i)
    for (const auto& [type, name] : props) {
      double v = 0;
      if (type == "float32")
        v = get_le<float>(buf, pos);
      else if (type == "double")
        v = get_le<double>(buf, pos);
      else if (type == "uint16")
        v = get_le<uint16_t>(buf, pos);
      else
        ADD_FAILURE() << "nsf does not write PLY type " << type;
      out[name].push_back(v);
    }
  EXPECT_EQ(pos, buf.size()) << "trailing bytes in " << path;
  return out;
}

// A legacy binary VTK UNSTRUCTURED_GRID file: POINTS, CELLS, CELL_TYPES and every field array
// (the dataset's TIME, the point data's arrays) by name, as doubles.
std::map<std::string, std::vector<double>> read_vtk(const fs::path& path) {
  const std::string buf = slurp(path);
  size_t pos = 0;
  EXPECT_EQ(next_line(buf, pos), "# vtk DataFile Version 3.0");
  next_line(buf, pos);  // title
  EXPECT_EQ(next_line(buf, pos), "BINARY");
  EXPECT_EQ(next_line(buf, pos), "DATASET UNSTRUCTURED_GRID");
  std::map<std::string, std::vector<double>> out;
  size_t n = 0;
  const auto read_block = [&](const std::string& key, const std::string& type, size_t count) {
    std::vector<double>& v = out[key];
    for (size_t i = 0; i < count; ++i) {
      if (type == "double")
        v.push_back(get_be<double>(buf, pos));
      else if (type == "int")
        v.push_back(get_be<int32_t>(buf, pos));
      else if (type == "unsigned_short")
        v.push_back(get_be<uint16_t>(buf, pos));
      else
        ADD_FAILURE() << "unexpected VTK type " << type;
    }
    EXPECT_EQ(buf[pos], '\n');
    ++pos;
  };
  while (pos < buf.size()) {
    std::istringstream ls(next_line(buf, pos));
    std::string word, name, type;
    size_t a = 0, b = 0;
    ls >> word;
    if (word == "FIELD") {
      size_t arrays = 0;
      ls >> name >> arrays;
      for (size_t i = 0; i < arrays; ++i) {
        std::istringstream arr(next_line(buf, pos));
        arr >> name >> a >> b >> type;
        out[name + ":components"] = {double(a)};
        read_block(name, type, a * b);
      }
    } else if (word == "POINTS") {
      ls >> n >> type;
      read_block("POINTS", type, 3 * n);
    } else if (word == "CELLS") {
      ls >> a >> b;
      read_block("CELLS", "int", b);
    } else if (word == "CELL_TYPES") {
      ls >> a;
      read_block("CELL_TYPES", "int", a);
    } else if (word == "POINT_DATA") {
      ls >> a;
      EXPECT_EQ(a, n);
    } else {
      ADD_FAILURE() << "unexpected VTK section '" << word << "'";
      break;
    }
  }
  return out;
}

// A VTU file with raw appended data: each DataArray by name, as doubles; TimeValue included.
std::map<std::string, std::vector<double>> read_vtu(const fs::path& path) {
  const std::string buf = slurp(path);
  std::map<std::string, std::vector<double>> out;
  const std::string marker = "<AppendedData encoding=\"raw\">";
  const size_t app = buf.find('_', buf.find(marker)) + 1;
  const std::string xml = buf.substr(0, app);
  EXPECT_NE(xml.find("byte_order=\"LittleEndian\""), std::string::npos);
  EXPECT_NE(xml.find("header_type=\"UInt64\""), std::string::npos);
  const std::regex array_re(
      "<DataArray type=\"(\\w+)\" Name=\"(\\w+)\" NumberOfComponents=\"\\d+\" "
      "format=\"appended\" offset=\"(\\d+)\"/>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), array_re);
       it != std::sregex_iterator(); ++it) {
    const std::string type = (*it)[1], name = (*it)[2];
    size_t pos = app + std::stoull((*it)[3]);
    const uint64_t bytes = get_le<uint64_t>(buf, pos);
    const size_t end = pos + bytes;
    std::vector<double>& v = out[name];
    while (pos < end) {
      if (type == "Float64")
        v.push_back(get_le<double>(buf, pos));
      else if (type == "Int64")
        v.push_back(static_cast<double>(get_le<int64_t>(buf, pos)));
      else if (type == "UInt16")
        v.push_back(get_le<uint16_t>(buf, pos));
      else if (type == "UInt8")
        v.push_back(get_le<uint8_t>(buf, pos));
      else
        ADD_FAILURE() << "unexpected VTU type " << type;
    }
  }
  std::smatch m;
  const std::regex time_re("Name=\"TimeValue\"[^>]*>([^<]+)</DataArray>");
  if (std::regex_search(xml, m, time_re)) out["TimeValue"] = {std::stod(m[1])};
  return out;
}

std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out;
  for (const Vec3& p : v) out.insert(out.end(), {p.x(), p.y(), p.z()});
  return out;
}

std::vector<double> flat(const std::vector<Mat3>& v) {  // row-major
  std::vector<double> out;
  for (const Mat3& m : v)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.push_back(m(i, j));
  return out;
}

// tau as the run file stores it: xx yy zz xy yz xz.
std::vector<double> flat_sym(const std::vector<Mat3>& v) {
  std::vector<double> out;
  for (const Mat3& m : v)
    out.insert(out.end(), {m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(1, 2), m(0, 2)});
  return out;
}

template <typename T>
std::vector<double> flat(const std::vector<T>& v) {
  return std::vector<double>(v.begin(), v.end());
}

std::vector<std::string> folder_names(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

class Export : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("nsf_export_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    run_ = (dir_ / "run.h5").string();
    nsf::testing::write_synthetic_run(run_, 4);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs export and expects success.
  void export_run(const std::string& args) {
    std::string out;
    ASSERT_EQ(run_cli("export '" + run_ + "' -q " + args, out), 0) << out;
  }

  fs::path dir_;
  std::string run_;
};

TEST_F(Export, PlyHoldsTheFrameAsFloats) {
  export_run("--format ply --out '" + (dir_ / "ply").string() + "'");
  nsf::RunReader run(run_);
  for (size_t k = 0; k < run.frame_count(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "run_%04zu.ply", k);
    auto ply = read_ply(dir_ / "ply" / name);
    const nsf::RunFrame f = run.read_frame(k);
    const size_t n = f.x.size();
    ASSERT_EQ(ply["x"].size(), n);
    for (size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(ply[std::string(1, "xyz"[a])][i], float(f.x[i][a]));
        EXPECT_EQ(ply[std::string("v_") + "xyz"[a]][i], float(f.v[i][a]));
      }
      EXPECT_EQ(ply["speed"][i], float(f.v[i].norm()));
      EXPECT_EQ(ply["von_mises"][i], float(nsf::von_mises(f.tau[i])));
      EXPECT_EQ(ply["material"][i], run.material()[i]);
      EXPECT_EQ(ply["object"][i], run.object()[i]);
    }
  }
}

TEST_F(Export, PlyDoublePositionsAreExact) {
  export_run("--format ply --double --frames -1 --out '" + (dir_ / "ply").string() + "'");
  // The one frame, and the record of which run the folder's run_* files came from.
  EXPECT_EQ(folder_names(dir_ / "ply"),
            (std::vector<std::string>{".nsf-export.json", "run_0003.ply"}));
  auto ply = read_ply(dir_ / "ply" / "run_0003.ply");
  const nsf::RunFrame f = nsf::RunReader(run_).read_frame(3);
  for (size_t i = 0; i < f.x.size(); ++i) EXPECT_EQ(ply["y"][i], f.x[i].y());
}

TEST_F(Export, LegacyVtkHoldsTheFrame) {
  export_run("--format vtk --frames 1:3 --out '" + (dir_ / "vtk").string() + "'");
  EXPECT_FALSE(fs::exists(dir_ / "vtk" / "run_0000.vtk"));
  EXPECT_FALSE(fs::exists(dir_ / "vtk" / "run_0003.vtk"));
  nsf::RunReader run(run_);
  for (size_t k : {1, 2}) {
    char name[32];
    std::snprintf(name, sizeof name, "run_%04zu.vtk", k);
    auto vtk = read_vtk(dir_ / "vtk" / name);
    const nsf::RunFrame f = run.read_frame(k);
    EXPECT_EQ(vtk["TIME"], std::vector<double>{f.time});
    EXPECT_EQ(vtk["POINTS"], flat(f.x));
    EXPECT_EQ(vtk["v"], flat(f.v));
    EXPECT_EQ(vtk["tau"], flat_sym(f.tau));
    EXPECT_EQ(vtk["tau:components"], std::vector<double>{6});
    EXPECT_EQ(vtk["F"], flat(f.F));
    EXPECT_EQ(vtk["speed"], flat(nsf::speeds(f.v)));
    EXPECT_EQ(vtk["von_mises"], flat(nsf::von_mises(f.tau)));
    EXPECT_EQ(vtk["material"], flat(run.material()));
    EXPECT_EQ(vtk["object"], flat(run.object()));
    ASSERT_EQ(vtk["CELLS"].size(), 2 * f.x.size());
    for (size_t i = 0; i < f.x.size(); ++i) {
      EXPECT_EQ(vtk["CELLS"][2 * i], 1);
      EXPECT_EQ(vtk["CELLS"][2 * i + 1], double(i));
    }
    EXPECT_EQ(vtk["CELL_TYPES"], std::vector<double>(f.x.size(), 1.0));  // VTK_VERTEX
  }
  // The series file gives ParaView the times.
  const auto series = nlohmann::json::parse(slurp(dir_ / "vtk" / "run.vtk.series"));
  ASSERT_EQ(series["files"].size(), 2u);
  EXPECT_EQ(series["files"][1]["name"], "run_0002.vtk");
  EXPECT_EQ(series["files"][1]["time"].get<double>(), run.times()[2]);
}

TEST_F(Export, VtuHoldsTheFrameAndPvdListsTheTimes) {
  export_run("--format vtu --out '" + (dir_ / "vtu").string() + "'");
  nsf::RunReader run(run_);
  for (size_t k = 0; k < run.frame_count(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "run_%04zu.vtu", k);
    auto vtu = read_vtu(dir_ / "vtu" / name);
    const nsf::RunFrame f = run.read_frame(k);
    const size_t n = f.x.size();
    EXPECT_EQ(vtu["TimeValue"], std::vector<double>{f.time});
    EXPECT_EQ(vtu["Points"], flat(f.x));
    EXPECT_EQ(vtu["v"], flat(f.v));
    EXPECT_EQ(vtu["tau"], flat_sym(f.tau));
    EXPECT_EQ(vtu["F"], flat(f.F));
    EXPECT_EQ(vtu["speed"], flat(nsf::speeds(f.v)));
    EXPECT_EQ(vtu["von_mises"], flat(nsf::von_mises(f.tau)));
    EXPECT_EQ(vtu["material"], flat(run.material()));
    EXPECT_EQ(vtu["object"], flat(run.object()));
    ASSERT_EQ(vtu["connectivity"].size(), n);
    ASSERT_EQ(vtu["offsets"].size(), n);
    EXPECT_EQ(vtu["types"], std::vector<double>(n, 1.0));  // VTK_VERTEX
    EXPECT_EQ(vtu["offsets"].back(), double(n));
  }
  const std::string pvd = slurp(dir_ / "vtu" / "run.pvd");
  const std::regex entry_re(
      "<DataSet timestep=\"([^\"]+)\" group=\"\" part=\"0\" file=\"([^\"]+)\"/>");
  std::vector<std::pair<double, std::string>> entries;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), entry_re);
       it != std::sregex_iterator(); ++it)
    entries.emplace_back(std::stod((*it)[1]), (*it)[2]);
  ASSERT_EQ(entries.size(), run.frame_count());
  for (size_t k = 0; k < entries.size(); ++k) {
    EXPECT_EQ(entries[k].first, run.times()[k]);
    EXPECT_TRUE(fs::exists(dir_ / "vtu" / entries[k].second)) << entries[k].second;
  }
  for (const auto& e : fs::directory_iterator(dir_ / "vtu"))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
}

// Before, every export wrote frame_NNNN files: a second run exported into the same folder
// overwrote the first one's frames, and the first run's .pvd then played the second run.
TEST_F(Export, TwoRunsInOneFolderKeepTheirOwnFramesAndCollections) {
  const std::string other = (dir_ / "other.h5").string();
  nsf::testing::write_synthetic_run(other, 2);
  const fs::path out = dir_ / "both";
  fs::create_directories(out);
  std::ofstream(out / "run_0007.vtu.tmp") << "left by a killed export";
  std::ofstream(out / "other_run_0001.vtu.tmp") << "another run's, not ours";
  export_run("--format vtu --out '" + out.string() + "'");
  std::string log;
  ASSERT_EQ(run_cli("export '" + other + "' -q --format vtu --out '" + out.string() + "'", log), 0)
      << log;
  EXPECT_FALSE(fs::exists(out / "run_0007.vtu.tmp"));  // a stale temp file of this run's export
  EXPECT_TRUE(fs::exists(out / "other_run_0001.vtu.tmp"));
  for (const auto& [name, frames] :
       {std::pair<std::string, size_t>{"run", 4}, std::pair<std::string, size_t>{"other", 2}}) {
    const std::string pvd = slurp(out / (name + ".pvd"));
    const std::regex file_re("file=\"([^\"]+)\"");
    size_t entries = 0;
    for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), file_re);
         it != std::sregex_iterator(); ++it, ++entries) {
      const std::string file = (*it)[1];
      EXPECT_EQ(file.rfind(name + "_", 0), 0u) << name << ".pvd lists " << file;
      EXPECT_TRUE(fs::exists(out / file)) << file;
    }
    EXPECT_EQ(entries, frames) << pvd;
  }
}

TEST_F(Export, BadInputFailsClearlyAndWritesNothing) {
  const std::string out = (dir_ / "out").string();
  const fs::path corrupt = dir_ / "corrupt.h5";
  std::ofstream(corrupt) << "this is not an HDF5 file";
  struct Case {
    std::string args, expect;
  };
  const std::vector<Case> cases = {
      {"'" + (dir_ / "missing.h5").string() + "' --format vtu", "missing.h5"},
      {"'" + corrupt.string() + "' --format vtu", "corrupt.h5"},
      {"'" + run_ + "' --format obj", "--format"},
      {"'" + run_ + "' --format vtu --frames 7", "--frames"},
      {"'" + run_ + "' --format vtu --frames 3:1", "--frames"},
      {"'" + run_ + "' --format vtu --frames 0:2:0", "step"},
      {"'" + run_ + "' --format vtu --frames x:y", "--frames"},
  };
  for (const Case& c : cases) {
    std::string output;
    EXPECT_NE(run_cli("export " + c.args + " --out '" + out + "'", output), 0) << c.args;
    EXPECT_NE(output.find(c.expect), std::string::npos) << c.args << "\n" << output;
    EXPECT_NE(output.find("error"), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

// Every frame as its own datasets, so that readers without hyperslabs (meshio) read them; the XDMF
// file names them frame by frame (read back by meshio and the Xdmf3 library in
// tests/check_export_readers.py).
TEST_F(Export, XdmfHoldsEveryFrameAsItsOwnDatasets) {
  export_run("--format xdmf --frames 1: --out '" + (dir_ / "xdmf").string() + "'");
  const fs::path h5 = dir_ / "xdmf" / "run.series.h5";
  ASSERT_TRUE(fs::exists(h5));
  EXPECT_FALSE(fs::exists(dir_ / "xdmf" / "run.series.h5.tmp"));
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const auto read = [&](const std::string& name) {
    std::vector<double> v;
    const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    EXPECT_GE(set, 0) << name;
    if (set < 0) return v;
    size_t n = 1;
    for (hsize_t d : nsf::h5::dataset_shape(file, name, h5.string())) n *= d;
    v.resize(n);
    EXPECT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0) << name;
    H5Dclose(set);
    return v;
  };
  nsf::RunReader run(run_);
  const size_t p = run.particle_count();
  std::vector<double> connectivity(p);
  for (size_t i = 0; i < p; ++i) connectivity[i] = double(i);
  EXPECT_EQ(read("/connectivity"), connectivity);
  EXPECT_EQ(read("/material"), flat(run.material()));
  EXPECT_EQ(read("/object"), flat(run.object()));
  EXPECT_EQ(H5Lexists(file, "/frames/0", H5P_DEFAULT), 0);  // not selected
  for (size_t k = 1; k < run.frame_count(); ++k) {
    const nsf::RunFrame f = run.read_frame(k);
    const std::string g = "/frames/" + std::to_string(k) + "/";
    EXPECT_EQ(read(g + "x"), flat(f.x));
    EXPECT_EQ(read(g + "v"), flat(f.v));
    EXPECT_EQ(read(g + "tau"), flat_sym(f.tau));
    EXPECT_EQ(read(g + "F"), flat(f.F));
    EXPECT_EQ(read(g + "speed"), flat(nsf::speeds(f.v)));
    EXPECT_EQ(read(g + "von_mises"), flat(nsf::von_mises(f.tau)));
  }
  H5Fclose(file);
  const std::string xml = slurp(dir_ / "xdmf" / "run.series.xdmf");
  const std::regex time_re(R"re(<Time Value="([^"]+)"/>)re");
  std::vector<double> times;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), time_re);
       it != std::sregex_iterator(); ++it)
    times.push_back(std::stod((*it)[1]));
  EXPECT_EQ(times, std::vector<double>(run.times().begin() + 1, run.times().end()));
  EXPECT_EQ(xml.find("HyperSlab"), std::string::npos);
  for (const char* name : {"x", "v", "speed", "von_mises", "tau", "F", "material", "object"})
    EXPECT_NE(xml.find("<Attribute Name=\"" + std::string(name) + "\""), std::string::npos) << name;
}

// Several runs in one command, each with its own files and collection.
TEST_F(Export, SeveralRunsInOneCommand) {
  const std::string other = (dir_ / "other.h5").string();
  nsf::testing::write_synthetic_run(other, 2);
  export_run("'" + other + "' --format vtu --out '" + (dir_ / "both").string() + "'");
  for (const char* file :
       {"run_0000.vtu", "run_0003.vtu", "run.pvd", "other_0001.vtu", "other.pvd"})
    EXPECT_TRUE(fs::exists(dir_ / "both" / file)) << file;
}

// The names of the files in a folder, with their contents.
std::map<std::string, std::string> folder(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    out[e.path().filename().string()] = slurp(e.path());
  return out;
}

// Every sweep names its runs train_0.h5, test_0.h5, ...: exported into one folder, the second run's
// files replaced the first one's with exit 0. A name in an export folder now belongs to one run
// file; re-exporting that run replaces its files, another run of that name is refused.
TEST_F(Export, ARunOfTheSameNameFromAnotherFolderIsRefusedNamingBoth) {
  const std::string a = (dir_ / "a" / "train_0.h5").string(),
                    b = (dir_ / "b" / "train_0.h5").string();
  fs::create_directories(dir_ / "a");
  fs::create_directories(dir_ / "b");
  nsf::testing::write_synthetic_run(a, 3);
  nsf::testing::write_synthetic_run(b, 5);
  const fs::path out = dir_ / "out";
  for (const char* format : {"vtu", "ply", "vtk", "xdmf"}) {
    SCOPED_TRACE(format);
    fs::remove_all(out);
    std::string log;
    ASSERT_EQ(run_cli("export '" + a + "' -q -f " + format + " -o '" + out.string() + "'", log), 0)
        << log;
    const auto before = folder(out);
    for (const std::string& f :
         {std::string("ply"), std::string("vtk"), std::string("vtu"), std::string("xdmf")}) {
      EXPECT_EQ(run_cli("export '" + b + "' -q -f " + f + " -o '" + out.string() + "'", log), 1)
          << log;
      EXPECT_NE(log.find("nsf: error: "), std::string::npos) << log;
      EXPECT_NE(log.find("'" + a + "'"), std::string::npos) << log;
      EXPECT_NE(log.find("'" + b + "'"), std::string::npos) << log;
      EXPECT_NE(log.find("another folder"), std::string::npos) << log;
      EXPECT_EQ(folder(out), before) << "the refused export wrote into " << out;
    }
    // The same run again: its own files are replaced, as before.
    EXPECT_EQ(run_cli("export '" + a + "' -q -f " + format + " -o '" + out.string() + "'", log), 0)
        << log;
    // Into another folder, b is fine.
    EXPECT_EQ(
        run_cli("export '" + b + "' -q -f " + format + " -o '" + (dir_ / "out_b").string() + "'",
                log),
        0)
        << log;
  }
}

TEST_F(Export, RunsOfTheSameNameInOneCommandAreRefusedBeforeAnythingIsWritten) {
  const std::string a = (dir_ / "a" / "train_0.h5").string(),
                    b = (dir_ / "b" / "train_0.h5").string();
  fs::create_directories(dir_ / "a");
  fs::create_directories(dir_ / "b");
  nsf::testing::write_synthetic_run(a, 3);
  nsf::testing::write_synthetic_run(b, 3);
  const fs::path out = dir_ / "out";
  std::string log;
  EXPECT_EQ(run_cli("export '" + a + "' '" + b + "' -q -o '" + out.string() + "'", log), 1) << log;
  EXPECT_NE(log.find("'" + a + "' and '" + b + "' have the same name 'train_0'"), std::string::npos)
      << log;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(run_cli("export '" + a + "' '" + (dir_ / "a" / ".." / "a" / "train_0.h5").string() +
                        "' -q -o '" + out.string() + "'",
                    log),
            1)
      << log;
  EXPECT_NE(log.find("is given twice"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
}

// Files of the run's name whose origin nothing records (an older nsf wrote them, or a person):
// never overwritten.
TEST_F(Export, FilesOfTheSameNameFromAnUnknownRunAreNotOverwritten) {
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  std::ofstream(out / "run_0002.vtu") << "someone else's frame";
  std::string log;
  EXPECT_EQ(run_cli("export '" + run_ + "' -q -o '" + out.string() + "'", log), 1) << log;
  EXPECT_NE(log.find("run_0002.vtu', whose run is not recorded"), std::string::npos) << log;
  EXPECT_EQ(folder(out),
            (std::map<std::string, std::string>{{"run_0002.vtu", "someone else's frame"}}));
}

}  // namespace
