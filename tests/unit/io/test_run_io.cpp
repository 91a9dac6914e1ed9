#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/run_format.h"
#include "io/run_reader.h"
#include "io/run_writer.h"

namespace fs = std::filesystem;
using nsf::Mat3;
using nsf::Vec3;

namespace {

// Every value depends on particle, frame and component, so a swapped index, a transposed matrix
// or a frame written to the wrong slot shows up as a mismatch.
double value(int p, int frame, int component, int field) {
  return 1000.0 * field + 10.0 * p + 0.5 * frame + 0.01 * component + 0.001;
}

Mat3 matrix(int p, int frame, int field) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = value(p, frame, 3 * i + j, field);
  return m;
}

nsf::Particles make_particles(int n) {
  nsf::Particles ps;
  for (int p = 0; p < n; ++p) {
    ps.add(Vec3(value(p, 0, 0, 1), value(p, 0, 1, 1), value(p, 0, 2, 1)), Vec3::Zero(), 0.5 + p,
           0.25 + p, nsf::MaterialPoint{}, static_cast<uint16_t>(p % 3),
           static_cast<uint16_t>(p % 2 + 7));
  }
  return ps;
}

void set_frame(nsf::Particles& ps, int frame) {
  for (int p = 0; p < static_cast<int>(ps.size()); ++p) {
    ps.x[p] = Vec3(value(p, frame, 0, 2), value(p, frame, 1, 2), value(p, frame, 2, 2));
    ps.v[p] = Vec3(value(p, frame, 0, 3), value(p, frame, 1, 3), value(p, frame, 2, 3));
    ps.C[p] = matrix(p, frame, 4);
    ps.F[p] = matrix(p, frame, 5);
    const Mat3 a = matrix(p, frame, 6);
    ps.tau[p] = a + a.transpose();
  }
}

nsf::SimSettings settings() {
  nsf::SimSettings s;
  s.dt = 2.5e-4;
  s.dx = 1.0 / 48;
  s.substeps = 17;
  return s;
}

const std::string kJson = R"({"name": "cube", "objects": [{"shape": "box"}], "note": "ünï"})";

class RunIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("nsf_run_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  // Writes `frames` frames of `n` particles and finishes.
  void write_run(const std::string& path, int n, int frames, nsf::RunWriterOptions opt = {}) {
    nsf::Particles ps = make_particles(n);
    nsf::RunWriter w(path, ps, settings(), "cube", kJson, opt);
    for (int f = 0; f < frames; ++f) {
      set_frame(ps, f);
      w.write_frame(ps, 0.1 * f);
    }
    w.set_attribute("mu", 2.5e5);
    w.set_attribute("label", "soft");
    w.set_attribute("seed", 42);
    w.finish();
  }

  std::string message_of_open(const std::string& path) {
    try {
      nsf::RunReader r(path);
    } catch (const nsf::Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "opening " << path << " did not throw";
    return "";
  }

  fs::path dir_;
};

void expect_frame(const nsf::RunFrame& got, int frame, int n) {
  nsf::Particles want = make_particles(n);
  set_frame(want, frame);
  ASSERT_EQ(got.x.size(), static_cast<size_t>(n));
  EXPECT_EQ(got.time, 0.1 * frame);
  for (int p = 0; p < n; ++p) {
    EXPECT_EQ(got.x[p], want.x[p]) << "p=" << p;
    EXPECT_EQ(got.v[p], want.v[p]) << "p=" << p;
    EXPECT_EQ(got.C[p], want.C[p]) << "p=" << p;
    EXPECT_EQ(got.F[p], want.F[p]) << "p=" << p;
    EXPECT_EQ(got.tau[p], want.tau[p]) << "p=" << p;
  }
}

TEST_F(RunIo, RoundTripsEveryDatasetAndAttribute) {
  const std::string path = file("run.h5");
  write_run(path, 5, 3);

  nsf::RunReader r(path);
  EXPECT_EQ(r.particle_count(), 5u);
  ASSERT_EQ(r.frame_count(), 3u);
  EXPECT_EQ(r.format_version(), 1);
  EXPECT_EQ(r.nsf_version(), NSF_VERSION);
  EXPECT_EQ(r.scene_name(), "cube");
  EXPECT_EQ(r.scene_json(), kJson);
  EXPECT_EQ(r.dt(), 2.5e-4);
  EXPECT_EQ(r.dx(), 1.0 / 48);
  EXPECT_EQ(r.substeps(), 17);
  EXPECT_EQ(r.attribute_double("mu"), 2.5e5);
  EXPECT_EQ(r.attribute_string("label"), "soft");
  EXPECT_EQ(r.attribute_int("seed"), 42);
  EXPECT_EQ(r.attribute_int("particle_count"), 5);
  EXPECT_EQ(r.attribute_string("format"), "nsf-run");
  EXPECT_FALSE(r.has_attribute("nope"));
  EXPECT_THROW(r.attribute_double("nope"), nsf::Error);
  EXPECT_THROW(r.attribute_int("label"), nsf::Error);

  const nsf::Particles rest = make_particles(5);
  EXPECT_EQ(r.rest_positions(), rest.X);
  EXPECT_EQ(r.mass(), rest.mass);
  EXPECT_EQ(r.volume(), rest.vol0);
  EXPECT_EQ(r.material(), rest.material);
  EXPECT_EQ(r.object(), rest.object);
  EXPECT_EQ(r.times(), (std::vector<double>{0.0, 0.1, 0.2}));
  for (int f = 0; f < 3; ++f) expect_frame(r.read_frame(f), f, 5);
  EXPECT_EQ(r.read_positions(2), r.read_frame(2).x);
  EXPECT_THROW(r.read_frame(3), nsf::Error);
}

TEST_F(RunIo, GzipRoundTripsExactly) {
  const std::string path = file("gz.h5");
  write_run(path, 7, 2, {1});
  nsf::RunReader r(path);
  expect_frame(r.read_frame(1), 1, 7);
}

// The documented layout, read with the plain HDF5 C API as h5py would: C row-major and τ as
// xx, yy, zz, xy, yz, xz. A round trip through RunReader alone would not catch a swap made
// consistently in writer and reader.
TEST_F(RunIo, FileLayoutMatchesDocs) {
  const std::string path = file("layout.h5");
  write_run(path, 2, 2);
  const auto read_row = [&](const char* name, hsize_t frame, hsize_t p, hsize_t width) {
    hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
    hid_t fs = H5Dget_space(d);
    const hsize_t start[3] = {frame, p, 0}, count[3] = {1, 1, width};
    H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, nullptr, count, nullptr);
    hid_t ms = H5Screate_simple(3, count, nullptr);
    std::vector<double> out(width);
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, out.data()), 0);
    H5Sclose(ms);
    H5Sclose(fs);
    H5Dclose(d);
    H5Fclose(f);
    return out;
  };
  nsf::Particles want = make_particles(2);
  set_frame(want, 1);
  const Mat3& C = want.C[1];
  EXPECT_EQ(read_row("/frames/C", 1, 1, 9),
            (std::vector<double>{C(0, 0), C(0, 1), C(0, 2), C(1, 0), C(1, 1), C(1, 2), C(2, 0),
                                 C(2, 1), C(2, 2)}));
  const Mat3& t = want.tau[1];
  EXPECT_EQ(read_row("/frames/tau", 1, 1, 6),
            (std::vector<double>{t(0, 0), t(1, 1), t(2, 2), t(0, 1), t(1, 2), t(0, 2)}));
}

TEST_F(RunIo, NothingAtFinalPathUntilFinish) {
  const std::string path = file("run.h5");
  nsf::Particles ps = make_particles(3);
  nsf::RunWriter w(path, ps, settings(), "cube", kJson);
  w.write_frame(ps, 0.0);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::exists(path + ".tmp"));
  w.finish();
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_THROW(w.write_frame(ps, 0.1), nsf::Error);
  EXPECT_THROW(w.finish(), nsf::Error);
}

TEST_F(RunIo, CallerCannotOverwriteLayoutAttributes) {
  nsf::Particles ps = make_particles(2);
  nsf::RunWriter w(file("run.h5"), ps, settings(), "cube", kJson);
  EXPECT_THROW(w.set_attribute("format", "other"), nsf::Error);
  EXPECT_THROW(w.set_attribute("dt", 1.0), nsf::Error);
  EXPECT_THROW(w.set_attribute("particle_count", 3), nsf::Error);
  EXPECT_NO_THROW(w.set_attribute("mu", 1.0));
  EXPECT_NO_THROW(w.set_attribute("mu", 2.0));  // a caller's own attribute may be replaced
}

// A caller's table (the ROM's latent per frame) as h5py sees it: rows × cols, row-major; the
// layout's own datasets cannot be overwritten this way.
TEST_F(RunIo, CallerTableIsAPlainTwoDimensionalDataset) {
  const std::string path = file("table.h5");
  nsf::Particles ps = make_particles(2);
  nsf::RunWriter w(path, ps, settings(), "cube", kJson);
  w.write_frame(ps, 0.0);
  EXPECT_THROW(w.write_table("/X", 1, 1, std::vector<double>{1.0}.data()), nsf::Error);
  EXPECT_THROW(w.write_table("/frames/z", 1, 1, std::vector<double>{1.0}.data()), nsf::Error);
  const std::vector<double> table{1, 2, 3, 4, 5, 6};
  w.write_table("/rom/latent", 2, 3, table.data());
  w.finish();
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t d = H5Dopen2(f, "/rom/latent", H5P_DEFAULT);
  ASSERT_GE(d, 0);
  hid_t space = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  EXPECT_EQ(H5Sget_simple_extent_ndims(space), 2);
  H5Sget_simple_extent_dims(space, dims, nullptr);
  EXPECT_EQ(dims[0], 2u);
  EXPECT_EQ(dims[1], 3u);
  std::vector<double> back(6);
  EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
  EXPECT_EQ(back, table);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  EXPECT_EQ(nsf::RunReader(path).frame_count(), 1u);
}

TEST_F(RunIo, WriterDestroyedWithoutFinishLeavesNoFiles) {
  {
    nsf::Particles ps = make_particles(3);
    nsf::RunWriter w(file("run.h5"), ps, settings(), "cube", kJson);
    w.write_frame(ps, 0.0);
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(RunIo, RejectedWriterLeavesOtherFilesAlone) {
  const std::string path = file("run.h5");
  std::ofstream(path + ".tmp") << "another writer's file";
  EXPECT_THROW(nsf::RunWriter(path, nsf::Particles{}, settings(), "cube", kJson), nsf::Error);
  EXPECT_TRUE(fs::exists(path + ".tmp"));
}

TEST_F(RunIo, SecondWriterToTheSamePathDoesNotDestroyTheFirst) {
  const std::string path = file("run.h5");
  nsf::Particles ps = make_particles(3);
  nsf::RunWriter first(path, ps, settings(), "cube", kJson);
  first.write_frame(ps, 0.0);
  try {
    nsf::RunWriter second(path, ps, settings(), "cube", kJson);
    ADD_FAILURE() << "a second writer to a run being written was accepted";
  } catch (const nsf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("another process"), std::string::npos) << e.what();
  }
  first.write_frame(ps, 0.1);
  first.finish();
  EXPECT_EQ(nsf::RunReader(path).frame_count(), 2u);
}

TEST_F(RunIo, StaleTemporaryFromAnInterruptedRunIsOverwritten) {
  const std::string path = file("run.h5");
  std::ofstream(path + ".tmp") << "left over by a crash";
  nsf::Particles ps = make_particles(3);
  nsf::RunWriter w(path, ps, settings(), "cube", kJson);
  w.write_frame(ps, 0.0);
  w.finish();
  EXPECT_EQ(nsf::RunReader(path).frame_count(), 1u);
}

TEST_F(RunIo, FinishReplacesAnOlderRun) {
  const std::string path = file("run.h5");
  write_run(path, 4, 1);
  write_run(path, 6, 2);
  nsf::RunReader r(path);
  EXPECT_EQ(r.particle_count(), 6u);
  EXPECT_EQ(r.frame_count(), 2u);
}

TEST_F(RunIo, RejectsAChangedParticleCount) {
  const std::string path = file("run.h5");
  nsf::Particles ps = make_particles(3);
  nsf::RunWriter w(path, ps, settings(), "cube", kJson);
  const nsf::Particles more = make_particles(4);
  try {
    w.write_frame(more, 0.0);
    FAIL() << "no error";
  } catch (const nsf::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST_F(RunIo, WriterMakesAMissingDirectory) {
  const std::string path = file("no/such/dir/run.h5");
  nsf::Particles ps = make_particles(3);
  nsf::RunWriter w(path, ps, settings(), "cube", kJson);
  w.write_frame(ps, 0.0);
  w.finish();
  EXPECT_EQ(nsf::RunReader(path).frame_count(), 1u);
}

TEST_F(RunIo, WriterFailsNamingAnUnwritablePath) {
  // A directory that cannot be made, even by root: its parent is a regular file.
  { std::ofstream(file("plain_file")) << "x"; }
  const std::string path = file("plain_file/dir/run.h5");
  nsf::Particles ps = make_particles(3);
  try {
    nsf::RunWriter w(path, ps, settings(), "cube", kJson);
    FAIL() << "no error";
  } catch (const nsf::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST_F(RunIo, MissingFileNamesTheFile) {
  const std::string path = file("absent.h5");
  const std::string msg = message_of_open(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST_F(RunIo, RandomBytesAreNotARun) {
  const std::string path = file("noise.h5");
  std::mt19937 rng(7);
  std::ofstream out(path, std::ios::binary);
  for (int i = 0; i < 4096; ++i) out.put(static_cast<char>(rng() & 0xff));
  out.close();
  const std::string msg = message_of_open(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an HDF5 file"), std::string::npos) << msg;
}

TEST_F(RunIo, TruncatedFileFailsAtOpen) {
  const std::string path = file("cut.h5");
  write_run(path, 50, 4);
  fs::resize_file(path, fs::file_size(path) / 2);
  const std::string msg = message_of_open(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
}

TEST_F(RunIo, HdfFileWithoutNsfLayoutIsRejected) {
  const std::string path = file("foreign.h5");
  H5Fclose(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  const std::string msg = message_of_open(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an nsf run file"), std::string::npos) << msg;
}

// Chunk checksums: a damaged frame is an error on read, not silently wrong positions.
TEST_F(RunIo, DamagedFrameDataIsAnErrorOnRead) {
  const std::string path = file("flipped.h5");
  write_run(path, 5, 2);
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const double marker = value(3, 1, 1, 2);  // x of particle 3, frame 1
  char pattern[sizeof(double)];
  std::memcpy(pattern, &marker, sizeof marker);
  const auto at = std::search(bytes.begin(), bytes.end(), pattern, pattern + sizeof pattern);
  ASSERT_NE(at, bytes.end());
  at[3] ^= 0x10;
  std::ofstream(path, std::ios::binary).write(bytes.data(), bytes.size());

  nsf::RunReader r(path);
  EXPECT_NO_THROW(r.read_frame(0));
  try {
    r.read_positions(1);
    FAIL() << "no error";
  } catch (const nsf::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/frames/x"), std::string::npos) << e.what();
  }
}

}  // namespace

// What the Python bindings read (python/src/run.cpp): a whole field in one read, as stored, and
// every root attribute by name and kind.
TEST_F(RunIo, ReadsEveryFrameOfAFieldAndListsTheAttributes) {
  const std::string path = file("all.h5");
  write_run(path, 4, 3);
  nsf::RunReader r(path);
  for (const char* field : {"x", "v", "C", "F", "tau"}) {
    const size_t width = nsf::RunReader::frame_field_width(field);
    std::vector<double> all(3 * 4 * width);
    r.read_all_frames(field, all.data(), all.size());
    for (int f = 0; f < 3; ++f) {
      const nsf::RunFrame frame = r.read_frame(f);
      std::vector<double> want(4 * width);
      for (int p = 0; p < 4; ++p) {
        double* row = want.data() + p * width;
        const std::string name = field;
        if (name == "x") nsf::run_format::pack_vec(frame.x[p], row);
        if (name == "v") nsf::run_format::pack_vec(frame.v[p], row);
        if (name == "C") nsf::run_format::pack_mat(frame.C[p], row);
        if (name == "F") nsf::run_format::pack_mat(frame.F[p], row);
        if (name == "tau") nsf::run_format::pack_sym(frame.tau[p], row);
      }
      EXPECT_EQ(std::vector<double>(all.begin() + f * 4 * width, all.begin() + (f + 1) * 4 * width),
                want)
          << field << " frame " << f;
    }
  }
  std::vector<double> short_buffer(3 * 4 * 3 - 1);
  EXPECT_THROW(r.read_all_frames("x", short_buffer.data(), short_buffer.size()), nsf::Error);
  EXPECT_THROW(nsf::RunReader::frame_field_width("y"), nsf::Error);

  const std::vector<std::string> names = r.attribute_names();
  for (const char* name : {"format", "format_version", "dt", "scene_json", "mu", "label", "seed"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  using Kind = nsf::RunReader::AttributeKind;
  EXPECT_EQ(r.attribute_kind("mu"), Kind::Float);
  EXPECT_EQ(r.attribute_kind("seed"), Kind::Integer);
  EXPECT_EQ(r.attribute_kind("label"), Kind::String);
  EXPECT_THROW(r.attribute_kind("nope"), nsf::Error);

  EXPECT_TRUE(r.has_dataset("/frames/x"));
  EXPECT_FALSE(r.has_dataset("/frames"));  // a group
  EXPECT_FALSE(r.has_dataset("/rom/latent"));
  EXPECT_FALSE(r.has_dataset("/nope/deeper/still"));
}
