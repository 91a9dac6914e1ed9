#include "io/run_writer.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <filesystem>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/temp_files.h"
#include "io/atomic_file.h"
#include "io/h5_util.h"
#include "io/run_format.h"
#include "io/xdmf_writer.h"

namespace nsf {

namespace {

namespace fs = std::filesystem;
using h5::Handle;

// HDF5 caps a chunk at 4 GiB. Whole-frame chunks make one frame one read; a huge run gets a few
// chunks per frame rather than a failure.
constexpr hsize_t kMaxChunkBytes = hsize_t(256) << 20;
constexpr hsize_t kTimeChunk = 256;

struct FrameField {
  const char* name;
  hsize_t width;
  const char* units;  // SI, stored as each dataset's "units" attribute ("1": dimensionless)
};
// Order matches Impl::fields.
constexpr std::array<FrameField, 5> kFields = {{{"/frames/x", run_format::kVectorWidth, "m"},
                                                {"/frames/v", run_format::kVectorWidth, "m/s"},
                                                {"/frames/C", run_format::kMatrixWidth, "1/s"},
                                                {"/frames/F", run_format::kMatrixWidth, "1"},
                                                {"/frames/tau", run_format::kSymWidth, "Pa"}}};

hsize_t chunk_rows(hsize_t rows, hsize_t row_bytes) {
  return std::clamp<hsize_t>(kMaxChunkBytes / row_bytes, 1, rows);
}

// dims[0] may be 0 for the per-frame datasets, which grow along it without limit.
Handle create_dataset(hid_t file_id, const std::string& name, hid_t type,
                      const std::vector<hsize_t>& dims, const std::vector<hsize_t>& chunk,
                      bool extendible, int gzip, const std::string& file) {
  const int rank = static_cast<int>(dims.size());
  std::vector<hsize_t> maxdims = dims;
  if (extendible) maxdims[0] = H5S_UNLIMITED;
  Handle space(h5::check(H5Screate_simple(rank, dims.data(), maxdims.data()), file, name),
               H5Sclose);
  Handle dcpl(h5::check(H5Pcreate(H5P_DATASET_CREATE), file, name), H5Pclose);
  h5::check_status(H5Pset_chunk(dcpl.get(), rank, chunk.data()), file, "chunking " + name);
  if (gzip > 0) {
    // Shuffling groups the bytes of neighbouring doubles, which is what lets deflate find
    // repetition in floating-point data.
    h5::check_status(H5Pset_shuffle(dcpl.get()), file, "shuffle filter on " + name);
    h5::check_status(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(gzip)), file,
                     "gzip filter on " + name);
  }
  // A per-chunk checksum turns a damaged file into a read error instead of silently wrong data.
  h5::check_status(H5Pset_fletcher32(dcpl.get()), file, "checksum filter on " + name);
  // No creation and modification times in the object header (HDF5 stores them by default): the
  // same run gives the same bytes, whenever and wherever it is written (`mpirun nsf sweep`).
  h5::check_status(H5Pset_obj_track_times(dcpl.get(), 0), file, "times of " + name);
  Handle lcpl(h5::check(H5Pcreate(H5P_LINK_CREATE), file, name), H5Pclose);
  h5::check_status(H5Pset_create_intermediate_group(lcpl.get(), 1), file, name);
  return Handle(h5::check(H5Dcreate2(file_id, name.c_str(), type, space.get(), lcpl.get(),
                                     dcpl.get(), H5P_DEFAULT),
                          file, "creating dataset " + name),
                H5Dclose);
}

// `units` ("" for none) becomes the dataset's "units" attribute.
void write_static(hid_t file_id, const std::string& name, hid_t file_type, hid_t mem_type,
                  hsize_t rows, hsize_t width, size_t elem_bytes, const void* data, int gzip,
                  const std::string& file, const std::string& units) {
  std::vector<hsize_t> dims{rows}, chunk{chunk_rows(rows, width * elem_bytes)};
  if (width > 1) {
    dims.push_back(width);
    chunk.push_back(width);
  }
  Handle set = create_dataset(file_id, name, file_type, dims, chunk, false, gzip, file);
  h5::check_status(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), file,
                   "writing dataset " + name);
  if (!units.empty()) h5::write_attribute(set.get(), "units", units, file);
}

template <typename T, typename Pack>
void flatten(const std::vector<T>& src, size_t width, Pack pack, std::vector<double>& out) {
  out.resize(src.size() * width);
  for (size_t i = 0; i < src.size(); ++i) pack(src[i], out.data() + i * width);
}

// Grows `set` by one frame (rows of `per_frame` elements, dims[1..] fixed) and writes it.
void append_frame(hid_t set, hsize_t frame, const std::vector<hsize_t>& per_frame,
                  const double* data, const std::string& file, const std::string& name) {
  const std::string what = "appending frame " + std::to_string(frame) + " to " + name;
  std::vector<hsize_t> dims{frame + 1}, start{frame}, count{1};
  for (hsize_t d : per_frame) {
    dims.push_back(d);
    start.push_back(0);
    count.push_back(d);
  }
  h5::check_status(H5Dset_extent(set, dims.data()), file, what);
  Handle fspace(h5::check(H5Dget_space(set), file, what), H5Sclose);
  h5::check_status(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr,
                                       count.data(), nullptr),
                   file, what);
  Handle mspace(h5::check(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr),
                          file, what),
                H5Sclose);
  h5::check_status(H5Dwrite(set, H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT, data),
                   file, what);
}

void check_sizes(const Particles& p, size_t expected, const std::string& file) {
  const size_t n = p.size();
  if (n != expected) {
    nsf::fail(file, ": run has ", expected, " particles but this state has ", n,
              " (the particle count must not change during a run)");
  }
  const bool consistent = p.X.size() == n && p.v.size() == n && p.C.size() == n &&
                          p.F.size() == n && p.tau.size() == n && p.mass.size() == n &&
                          p.vol0.size() == n && p.material.size() == n && p.object.size() == n;
  if (!consistent) nsf::fail(file, ": particle arrays have different lengths");
}

}  // namespace

struct RunWriter::Impl {
  std::string path, tmp;
  hsize_t particles = 0;
  TempFileRegistration registration;  // a fatal signal deletes tmp (core/temp_files.h)
  Handle file;
  std::array<Handle, kFields.size()> fields;
  Handle time;
  hsize_t frames = 0;
  std::vector<double> times;  // of the frames written, for the XDMF sidecar
  bool created = false;
  bool finished = false;
  bool broken = false;  // a write failed part-way, so the datasets may disagree on frame count
  std::vector<double> buf;

  ~Impl() {
    if (finished || !created) return;  // never delete a .tmp this writer did not create
    h5::QuietErrors quiet;
    for (Handle& h : fields) h.reset();
    time.reset();
    file.reset();
    std::error_code ignored;
    fs::remove(tmp, ignored);
  }

  void write_attributes(const SimSettings& s, const std::string& scene_name,
                        const std::string& scene_json) {
    const hid_t root = file.get();
    h5::write_attribute(root, "format", std::string(run_format::kFormat), tmp);
    h5::write_attribute(root, "format_version", int64_t{run_format::kFormatVersion}, tmp);
    h5::write_attribute(root, "nsf_version", std::string(NSF_VERSION), tmp);
    h5::write_attribute(root, "scene_name", scene_name, tmp);
    h5::write_attribute(root, "scene_json", scene_json, tmp);
    h5::write_attribute(root, "dt", s.dt, tmp);
    h5::write_attribute(root, "dx", s.dx, tmp);
    h5::write_attribute(root, "substeps", int64_t{s.substeps}, tmp);
    h5::write_attribute(root, "particle_count", static_cast<int64_t>(particles), tmp);
  }

  void write_static_data(const Particles& p, int gzip) {
    const hid_t f = file.get();
    flatten(p.X, 3, run_format::pack_vec, buf);
    write_static(f, "/X", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, particles, 3, 8, buf.data(), gzip, tmp,
                 "m");
    write_static(f, "/mass", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, particles, 1, 8, p.mass.data(),
                 gzip, tmp, "kg");
    write_static(f, "/volume", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, particles, 1, 8, p.vol0.data(),
                 gzip, tmp, "m^3");
    write_static(f, "/material", H5T_STD_U16LE, H5T_NATIVE_UINT16, particles, 1, 2,
                 p.material.data(), gzip, tmp, "1");
    write_static(f, "/object", H5T_STD_U16LE, H5T_NATIVE_UINT16, particles, 1, 2, p.object.data(),
                 gzip, tmp, "1");
  }

  void create_frame_datasets(int gzip) {
    for (size_t k = 0; k < kFields.size(); ++k) {
      const hsize_t w = kFields[k].width;
      fields[k] = create_dataset(file.get(), kFields[k].name, H5T_IEEE_F64LE, {0, particles, w},
                                 {1, chunk_rows(particles, w * 8), w}, true, gzip, tmp);
      h5::write_attribute(fields[k].get(), "units", std::string(kFields[k].units), tmp);
    }
    time =
        create_dataset(file.get(), "/frames/time", H5T_IEEE_F64LE, {0}, {kTimeChunk}, true, 0, tmp);
    h5::write_attribute(time.get(), "units", std::string("s"), tmp);
  }

  void write_frame(const Particles& p, double t) {
    const auto put = [&](size_t k) {
      append_frame(fields[k].get(), frames, {particles, kFields[k].width}, buf.data(), tmp,
                   kFields[k].name);
    };
    flatten(p.x, 3, run_format::pack_vec, buf);
    put(0);
    flatten(p.v, 3, run_format::pack_vec, buf);
    put(1);
    flatten(p.C, 9, run_format::pack_mat, buf);
    put(2);
    flatten(p.F, 9, run_format::pack_mat, buf);
    put(3);
    flatten(p.tau, 6, run_format::pack_sym, buf);
    put(4);
    append_frame(time.get(), frames, {}, &t, tmp, "/frames/time");
  }
};

// A stale <path>.tmp from an interrupted run is replaced, but replacing one that another live
// process is still writing would destroy that run. HDF5 holds an flock() on files it has open for
// writing, so a lock we cannot take means a live writer. (A link at tmp is not opened: O_NOFOLLOW.)
static void refuse_if_being_written(const std::string& tmp, const std::string& path) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  const bool busy = ::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  if (busy)
    nsf::fail(path, ": another process is writing this run right now (", tmp,
              " is locked); wait for it to finish or choose another output path");
}

RunWriter::RunWriter(const std::string& path, const Particles& p, const SimSettings& s,
                     const std::string& scene_name, const std::string& scene_json,
                     const RunWriterOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.path = path;
  w.tmp = path + ".tmp";
  if (p.size() == 0) nsf::fail(path, ": cannot write a run with no particles");
  check_sizes(p, p.size(), path);
  if (options.gzip_level < 0 || options.gzip_level > 9) {
    nsf::fail(path, ": gzip level must be 0..9, got ", options.gzip_level);
  }
  w.particles = p.size();

  h5::QuietErrors quiet;
  if (options.gzip_level > 0 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) {
    h5::fail(w.tmp, "this HDF5 library has no gzip filter");
  }
  refuse_if_being_written(w.tmp, path);
  // Like `nsf sweep` and `nsf train`, every command that writes a run makes its directory.
  if (const fs::path dir = fs::path(path).parent_path(); !dir.empty()) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec)
      nsf::fail(path, ": cannot create the directory ", dir.string(), " (", ec.message(), ")");
  }
  w.file = Handle(h5::create_exclusive(w.tmp, path), H5Fclose);
  w.registration = TempFileRegistration(w.tmp);
  w.created = true;
  w.write_attributes(s, scene_name, scene_json);
  w.write_static_data(p, options.gzip_level);
  w.create_frame_datasets(options.gzip_level);
}

RunWriter::~RunWriter() = default;
RunWriter::RunWriter(RunWriter&&) noexcept = default;
RunWriter& RunWriter::operator=(RunWriter&&) noexcept = default;

RunWriter::Impl& RunWriter::live(const char* call) const {
  if (!impl_) nsf::fail("RunWriter::", call, " on a moved-from writer");
  if (impl_->finished) nsf::fail(impl_->path, ": RunWriter::", call, " after finish()");
  if (impl_->broken) {
    nsf::fail(impl_->path, ": RunWriter::", call,
              " after an earlier write failed; the run is lost");
  }
  return *impl_;
}

void RunWriter::write_frame(const Particles& p, double time) {
  Impl& w = live("write_frame");
  check_sizes(p, w.particles, w.path);
  h5::QuietErrors quiet;
  w.broken = true;
  w.write_frame(p, time);
  w.broken = false;
  ++w.frames;
  w.times.push_back(time);
}

namespace {
// The layout's own attributes: overwriting one would make the file lie about itself.
void check_not_reserved(const std::string& name, const std::string& file) {
  for (const char* r : {"format", "format_version", "nsf_version", "scene_name", "scene_json", "dt",
                        "dx", "substeps", "particle_count"}) {
    if (name == r) nsf::fail(file, ": attribute '", name, "' is set by RunWriter itself");
  }
}
}  // namespace

void RunWriter::write_table(const std::string& name, size_t rows, size_t cols, const double* data) {
  Impl& w = live("write_table");
  for (const char* own : {"/X", "/mass", "/volume", "/material", "/object", "/frames"})
    if (name.rfind(own, 0) == 0)
      nsf::fail(w.path, ": dataset '", name, "' is part of the run layout, written by RunWriter");
  if (rows == 0 || cols == 0) nsf::fail(w.path, ": table '", name, "' is empty");
  h5::QuietErrors quiet;
  write_static(w.file.get(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rows, cols, 8, data, 0, w.tmp,
               "");
}

void RunWriter::set_attribute(const std::string& name, double value) {
  Impl& w = live("set_attribute");
  check_not_reserved(name, w.path);
  h5::QuietErrors quiet;
  h5::write_attribute(w.file.get(), name, value, w.tmp);
}

void RunWriter::set_attribute(const std::string& name, const std::string& value) {
  Impl& w = live("set_attribute");
  check_not_reserved(name, w.path);
  h5::QuietErrors quiet;
  h5::write_attribute(w.file.get(), name, value, w.tmp);
}

void RunWriter::set_int_attribute(const std::string& name, int64_t value) {
  Impl& w = live("set_attribute");
  check_not_reserved(name, w.path);
  h5::QuietErrors quiet;
  h5::write_attribute(w.file.get(), name, value, w.tmp);
}

void RunWriter::finish() {
  Impl& w = live("finish");
  h5::QuietErrors quiet;
  bool closed = w.time.reset();
  for (Handle& h : w.fields) closed = h.reset() && closed;
  closed = w.file.reset() && closed;  // flushes everything to disk
  if (!closed) h5::fail(w.tmp, "closing the file failed (disk full?)");
  // The sidecar first: a run never appears without it, and one left by a failed rename below
  // describes a run that is not there (harmless; the next run of that name replaces it).
  const std::string xdmf = xdmf_path_for(w.path);
  write_file_atomic(xdmf, run_xdmf(fs::path(w.path).filename().string(),
                                   static_cast<size_t>(w.particles), w.times));
  std::error_code ec;
  fs::rename(w.tmp, w.path, ec);
  if (ec) nsf::fail(w.path, ": cannot move ", w.tmp, " into place: ", ec.message());
  w.registration.release();
  w.finished = true;
}

size_t RunWriter::frames_written() const {
  return impl_ ? impl_->frames : 0;
}

const std::string& RunWriter::path() const {
  if (!impl_) nsf::fail("RunWriter::path on a moved-from writer");
  return impl_->path;
}

}  // namespace nsf
