#include "io/run_reader.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string_view>
#include <system_error>

#include "core/error.h"
#include "io/h5_util.h"
#include "io/run_format.h"

namespace nsf {

namespace {

namespace fs = std::filesystem;
using h5::Handle;

enum Field { kX, kV, kC, kF, kTau, kFieldCount };
constexpr std::array<const char*, kFieldCount> kFieldNames = {"/frames/x", "/frames/v", "/frames/C",
                                                              "/frames/F", "/frames/tau"};
constexpr std::array<hsize_t, kFieldCount> kFieldWidths = {
    run_format::kVectorWidth, run_format::kVectorWidth, run_format::kMatrixWidth,
    run_format::kMatrixWidth, run_format::kSymWidth};

std::string shape_text(const std::vector<hsize_t>& dims) {
  std::string s;
  for (size_t i = 0; i < dims.size(); ++i) s += (i ? "x" : "") + std::to_string(dims[i]);
  return dims.empty() ? "scalar" : s;
}

// A dataset's declared shape against the bytes the file holds of it, before anything of that size
// is allocated: a file of a few kilobytes may declare 2^40 frames (chunks never written read as
// fill values), which used to end in std::bad_alloc naming no file. Deflate inflates its input
// at most 1032 times; nsf writes every chunk of every dataset.
void check_declared_size(hid_t set, const std::string& name, const std::vector<hsize_t>& dims,
                         size_t element_bytes, const std::string& path) {
  constexpr double kMaxInflation = 1100, kSlackBytes = 1 << 20;
  double values = 1;
  for (hsize_t d : dims) values *= double(d);
  const double declared = values * double(element_bytes);
  const double stored = double(H5Dget_storage_size(set));
  if (declared <= kMaxInflation * stored + kSlackBytes) return;
  char what[160];
  std::snprintf(what, sizeof what, "%.0f values (%.3g bytes)", values, declared);
  nsf::fail(path, ": dataset ", name, " declares ", what, ", more than the file holds (",
            std::uint64_t(stored), " bytes of it are stored, which inflate to at most ",
            kMaxInflation, " times as many): the file is damaged or was not written by nsf");
}

Handle open_dataset(hid_t file, const std::string& name, const std::vector<hsize_t>& expected,
                    H5T_class_t cls, const std::string& path) {
  const std::vector<hsize_t> dims = h5::dataset_shape(file, name, path);
  if (dims != expected) {
    nsf::fail(path, ": dataset ", name, " has shape ", shape_text(dims), ", expected ",
              shape_text(expected));
  }
  Handle set(h5::check(H5Dopen2(file, name.c_str(), H5P_DEFAULT), path, "opening " + name),
             H5Dclose);
  Handle type(h5::check(H5Dget_type(set.get()), path, name), H5Tclose);
  if (H5Tget_class(type.get()) != cls) {
    nsf::fail(path, ": dataset ", name, " has the wrong element type (expected ",
              cls == H5T_FLOAT ? "floating point" : "integer", ")");
  }
  check_declared_size(set.get(), name, dims, H5Tget_size(type.get()), path);
  return set;
}

template <typename T>
std::vector<T> read_whole(hid_t file, const std::string& name, const std::vector<hsize_t>& expected,
                          H5T_class_t cls, hid_t mem_type, const std::string& path) {
  Handle set = open_dataset(file, name, expected, cls, path);
  size_t n = 1;
  for (hsize_t d : expected) n *= d;
  std::vector<T> out(n);
  h5::check_status(H5Dread(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), path,
                   "reading " + name);
  return out;
}

// Reads frame k (P rows of `width` doubles) of a per-frame dataset.
void read_frame_rows(hid_t set, hsize_t k, hsize_t particles, hsize_t width,
                     std::vector<double>& out, const std::string& path, const char* name) {
  const std::string what = "reading frame " + std::to_string(k) + " of " + name;
  out.resize(particles * width);
  const hsize_t start[3] = {k, 0, 0};
  const hsize_t count[3] = {1, particles, width};
  Handle fspace(h5::check(H5Dget_space(set), path, what), H5Sclose);
  h5::check_status(
      H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), path,
      what);
  Handle mspace(h5::check(H5Screate_simple(3, count, nullptr), path, what), H5Sclose);
  h5::check_status(
      H5Dread(set, H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT, out.data()), path,
      what);
}

// The per-frame dataset called `field` ("x", "v", "C", "F", "tau"), or kFieldCount.
int field_index(const std::string& field) {
  for (int k = 0; k < kFieldCount; ++k)
    if (field == kFieldNames[k] + std::string_view("/frames/").size()) return k;
  return kFieldCount;
}

herr_t collect_name(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

template <typename T, typename Unpack>
std::vector<T> unflatten(const std::vector<double>& in, size_t width, Unpack unpack) {
  std::vector<T> out(in.size() / width);
  for (size_t i = 0; i < out.size(); ++i) out[i] = unpack(in.data() + i * width);
  return out;
}

}  // namespace

struct RunReader::Impl {
  std::string path;
  Handle file;
  hsize_t particles = 0, frames = 0;
  int format_version = 0, substeps = 0;
  std::string nsf_version, scene_name, scene_json;
  double dt = 0, dx = 0;
  std::vector<Vec3> X;
  std::vector<double> mass, volume, times;
  std::vector<uint16_t> material, object;
  std::array<Handle, kFieldCount> fields;

  void open() {
    std::error_code ec;
    if (!fs::exists(path, ec)) nsf::fail(path, ": no such file");
    if (fs::is_directory(path, ec)) nsf::fail(path, ": is a directory, not a run file");
    if (H5Fis_hdf5(path.c_str()) <= 0) {
      h5::fail(path, "not an HDF5 file (a different kind of file, or a damaged header)");
    }
    file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) h5::fail(path, "cannot open: the file is truncated or damaged");
  }

  void read_attributes() {
    const hid_t root = file.get();
    if (!h5::has_attribute(root, "format")) {
      nsf::fail(path, ": not an nsf run file (no 'format' attribute)");
    }
    const std::string format = h5::read_attribute_string(root, "format", path);
    if (format != run_format::kFormat) {
      nsf::fail(path, ": not an nsf run file (format is '", format, "', expected '",
                run_format::kFormat, "')");
    }
    const int64_t version = h5::read_attribute_int(root, "format_version", path);
    if (version < 1 || version > run_format::kFormatVersion) {
      nsf::fail(path, ": format_version ", version, " is not one this nsf reads (1..",
                run_format::kFormatVersion, "); a newer nsf wrote it?");
    }
    format_version = static_cast<int>(version);
    nsf_version = h5::read_attribute_string(root, "nsf_version", path);
    scene_name = h5::read_attribute_string(root, "scene_name", path);
    scene_json = h5::read_attribute_string(root, "scene_json", path);
    dt = h5::read_attribute_double(root, "dt", path);
    dx = h5::read_attribute_double(root, "dx", path);
    substeps = static_cast<int>(h5::read_attribute_int(root, "substeps", path));
    const int64_t count = h5::read_attribute_int(root, "particle_count", path);
    if (count <= 0) nsf::fail(path, ": particle_count is ", count);
    particles = static_cast<hsize_t>(count);
  }

  void read_static() {
    const hid_t f = file.get();
    const hsize_t P = particles;
    X = unflatten<Vec3>(read_whole<double>(f, "/X", {P, 3}, H5T_FLOAT, H5T_NATIVE_DOUBLE, path), 3,
                        run_format::unpack_vec);
    mass = read_whole<double>(f, "/mass", {P}, H5T_FLOAT, H5T_NATIVE_DOUBLE, path);
    volume = read_whole<double>(f, "/volume", {P}, H5T_FLOAT, H5T_NATIVE_DOUBLE, path);
    material = read_whole<uint16_t>(f, "/material", {P}, H5T_INTEGER, H5T_NATIVE_UINT16, path);
    object = read_whole<uint16_t>(f, "/object", {P}, H5T_INTEGER, H5T_NATIVE_UINT16, path);
  }

  void open_frames() {
    const hid_t f = file.get();
    const std::vector<hsize_t> time_shape = h5::dataset_shape(f, "/frames/time", path);
    if (time_shape.size() != 1) nsf::fail(path, ": /frames/time is not one-dimensional");
    frames = time_shape[0];
    times = read_whole<double>(f, "/frames/time", {frames}, H5T_FLOAT, H5T_NATIVE_DOUBLE, path);
    for (int k = 0; k < kFieldCount; ++k) {
      fields[k] =
          open_dataset(f, kFieldNames[k], {frames, particles, kFieldWidths[k]}, H5T_FLOAT, path);
    }
  }
};

RunReader::RunReader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  h5::QuietErrors quiet;
  impl_->path = path;
  impl_->open();
  impl_->read_attributes();
  impl_->read_static();
  impl_->open_frames();
}

RunReader::~RunReader() = default;
RunReader::RunReader(RunReader&&) noexcept = default;
RunReader& RunReader::operator=(RunReader&&) noexcept = default;

const std::string& RunReader::path() const {
  return impl_->path;
}
size_t RunReader::particle_count() const {
  return impl_->particles;
}
size_t RunReader::frame_count() const {
  return impl_->frames;
}
int RunReader::format_version() const {
  return impl_->format_version;
}
const std::string& RunReader::nsf_version() const {
  return impl_->nsf_version;
}
const std::string& RunReader::scene_name() const {
  return impl_->scene_name;
}
const std::string& RunReader::scene_json() const {
  return impl_->scene_json;
}
double RunReader::dt() const {
  return impl_->dt;
}
double RunReader::dx() const {
  return impl_->dx;
}
int RunReader::substeps() const {
  return impl_->substeps;
}

bool RunReader::has_attribute(const std::string& name) const {
  h5::QuietErrors quiet;
  return h5::has_attribute(impl_->file.get(), name);
}

double RunReader::attribute_double(const std::string& name) const {
  h5::QuietErrors quiet;
  return h5::read_attribute_double(impl_->file.get(), name, impl_->path);
}

int64_t RunReader::attribute_int(const std::string& name) const {
  h5::QuietErrors quiet;
  return h5::read_attribute_int(impl_->file.get(), name, impl_->path);
}

std::string RunReader::attribute_string(const std::string& name) const {
  h5::QuietErrors quiet;
  return h5::read_attribute_string(impl_->file.get(), name, impl_->path);
}

const std::vector<Vec3>& RunReader::rest_positions() const {
  return impl_->X;
}
const std::vector<double>& RunReader::mass() const {
  return impl_->mass;
}
const std::vector<double>& RunReader::volume() const {
  return impl_->volume;
}
const std::vector<uint16_t>& RunReader::material() const {
  return impl_->material;
}
const std::vector<uint16_t>& RunReader::object() const {
  return impl_->object;
}
const std::vector<double>& RunReader::times() const {
  return impl_->times;
}

std::vector<std::string> RunReader::attribute_names() const {
  h5::QuietErrors quiet;
  std::vector<std::string> names;
  hsize_t index = 0;
  h5::check_status(
      H5Aiterate2(impl_->file.get(), H5_INDEX_NAME, H5_ITER_INC, &index, collect_name, &names),
      impl_->path, "listing the attributes");
  return names;
}

RunReader::AttributeKind RunReader::attribute_kind(const std::string& name) const {
  h5::QuietErrors quiet;
  const std::string& path = impl_->path;
  Handle attr(h5::check(H5Aopen(impl_->file.get(), name.c_str(), H5P_DEFAULT), path,
                        "no attribute '" + name + "'"),
              H5Aclose);
  Handle type(h5::check(H5Aget_type(attr.get()), path, "attribute " + name), H5Tclose);
  switch (H5Tget_class(type.get())) {
    case H5T_INTEGER:
      return AttributeKind::Integer;
    case H5T_FLOAT:
      return AttributeKind::Float;
    case H5T_STRING:
      return AttributeKind::String;
    default:
      return AttributeKind::Other;
  }
}

size_t RunReader::frame_field_width(const std::string& field) {
  const int k = field_index(field);
  if (k == kFieldCount)
    nsf::fail("no per-frame field '", field, "' in a run file (x, v, C, F and tau are)");
  return kFieldWidths[k];
}

void RunReader::read_all_frames(const std::string& field, double* out, size_t size) const {
  const Impl& r = *impl_;
  const size_t width = frame_field_width(field);
  if (size != r.frames * r.particles * width)
    nsf::fail(r.path, ": ", field, " of every frame is ", r.frames, "x", r.particles, "x", width,
              " doubles, the buffer holds ", size);
  h5::QuietErrors quiet;
  const int k = field_index(field);
  h5::check_status(
      H5Dread(r.fields[k].get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out), r.path,
      std::string("reading ") + kFieldNames[k]);
}

RunFrame RunReader::read_frame(size_t k) const {
  const Impl& r = *impl_;
  if (k >= r.frames) nsf::fail(r.path, ": no frame ", k, " (the file has ", r.frames, ")");
  h5::QuietErrors quiet;
  std::vector<double> buf;
  const auto read = [&](Field f) {
    read_frame_rows(r.fields[f].get(), k, r.particles, kFieldWidths[f], buf, r.path,
                    kFieldNames[f]);
    return buf;
  };
  RunFrame out;
  out.time = r.times[k];
  out.x = unflatten<Vec3>(read(kX), 3, run_format::unpack_vec);
  out.v = unflatten<Vec3>(read(kV), 3, run_format::unpack_vec);
  out.C = unflatten<Mat3>(read(kC), 9, run_format::unpack_mat);
  out.F = unflatten<Mat3>(read(kF), 9, run_format::unpack_mat);
  out.tau = unflatten<Mat3>(read(kTau), 6, run_format::unpack_sym);
  return out;
}

std::vector<double> RunReader::read_table(const std::string& name, size_t& rows,
                                          size_t& cols) const {
  h5::QuietErrors quiet;
  const hid_t f = impl_->file.get();
  const std::vector<hsize_t> dims = h5::dataset_shape(f, name, impl_->path);
  if (dims.size() != 2)
    nsf::fail(impl_->path, ": ", name, " has shape ", shape_text(dims), ", expected a table");
  rows = size_t(dims[0]), cols = size_t(dims[1]);
  return read_whole<double>(f, name, dims, H5T_FLOAT, H5T_NATIVE_DOUBLE, impl_->path);
}

bool RunReader::has_dataset(const std::string& name) const {
  h5::QuietErrors quiet;
  // Each link of the path in turn: HDF5 fails, rather than answer no, below a missing group.
  for (size_t end = name.find('/', 1);; end = name.find('/', end + 1)) {
    const std::string prefix = name.substr(0, end);
    if (H5Lexists(impl_->file.get(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (end == std::string::npos) break;
  }
  return Handle(H5Dopen2(impl_->file.get(), name.c_str(), H5P_DEFAULT), H5Dclose).valid();
}

std::vector<Vec3> RunReader::read_positions(size_t k) const {
  return unflatten<Vec3>(read_frame_field(k, "x"), 3, run_format::unpack_vec);
}

std::vector<double> RunReader::read_frame_field(size_t k, const std::string& field) const {
  const Impl& r = *impl_;
  const size_t width = frame_field_width(field);
  if (k >= r.frames) nsf::fail(r.path, ": no frame ", k, " (the file has ", r.frames, ")");
  h5::QuietErrors quiet;
  const int f = field_index(field);
  std::vector<double> buf;
  read_frame_rows(r.fields[f].get(), k, r.particles, width, buf, r.path, kFieldNames[f]);
  return buf;
}

}  // namespace nsf
