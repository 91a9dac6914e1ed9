#include "io/xdmf_series.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <utility>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/temp_files.h"
#include "io/atomic_file.h"
#include "io/frame_fields.h"
#include "io/h5_util.h"
#include "io/xml_escape.h"

namespace nsf {

namespace {

namespace fs = std::filesystem;
using h5::Handle;

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// A whole dataset written at once: contiguous and unfiltered, which every HDF5 reader reads.
void write_dataset(hid_t file, const std::string& name, hid_t file_type, hid_t mem_type,
                   const std::vector<hsize_t>& dims, const void* data, const std::string& path) {
  Handle space(
      h5::check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), path, name),
      H5Sclose);
  Handle lcpl(h5::check(H5Pcreate(H5P_LINK_CREATE), path, name), H5Pclose);
  h5::check_status(H5Pset_create_intermediate_group(lcpl.get(), 1), path, name);
  Handle set(h5::check(H5Dcreate2(file, name.c_str(), file_type, space.get(), lcpl.get(),
                                  H5P_DEFAULT, H5P_DEFAULT),
                       path, "creating dataset " + name),
             H5Dclose);
  h5::check_status(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), path,
                   "writing dataset " + name);
  if (!set.reset()) h5::fail(path, "closing dataset " + name);
}

const char* attribute_type(int components) {
  switch (components) {
    case 1:
      return "Scalar";
    case 3:
      return "Vector";
    case 9:
      return "Tensor";
    default:
      return "Matrix";  // tau's 6 components are not in XDMF's Tensor6 order
  }
}

std::string dims(size_t p, int width) {
  return width == 1 ? std::to_string(p) : std::to_string(p) + " " + std::to_string(width);
}

struct Array {
  std::string name, dataset;  // dataset: "" for per-frame ones, /frames/<k>/<name>
  int width;
  bool index;
};

void data_item(std::ostream& x, const std::string& file, const std::string& dataset, size_t p,
               int width, bool index) {
  x << "          <DataItem Dimensions=\"" << dims(p, width) << "\" NumberType=\""
    << (index ? "UInt\" Precision=\"2" : "Float\" Precision=\"8") << "\" Format=\"HDF\">" << file
    << ":" << dataset << "</DataItem>\n";
}

}  // namespace

struct XdmfSeriesWriter::Impl {
  std::string xdmf_path, h5_path, tmp;
  std::vector<uint16_t> material, object;
  TempFileRegistration registration;  // a fatal signal deletes tmp (core/temp_files.h)
  Handle file;
  bool created = false, finished = false;
  std::vector<std::pair<size_t, double>> steps;  // run frame, time
  std::vector<Array> arrays;                     // per-frame float arrays after x

  ~Impl() {
    if (finished || !created) return;  // never delete a .tmp this writer did not create
    h5::QuietErrors quiet;
    file.reset();
    std::error_code ignored;
    fs::remove(tmp, ignored);
  }

  std::string xdmf() const {
    const std::string h5 = xml_escape(fs::path(h5_path).filename().string());
    const size_t p = material.size();
    std::ostringstream x;
    x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
      << "    <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& [k, time] : steps) {
      const std::string frame = "/frames/" + std::to_string(k) + "/";
      x << "      <Grid Name=\"frame_" << k << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << num(time) << "\"/>\n"
        << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << p
        << "\" NodesPerElement=\"1\">\n"
        << "          <DataItem Dimensions=\"" << p << " 1\" NumberType=\"Int\" Precision=\"8\" "
        << "Format=\"HDF\">" << h5 << ":/connectivity</DataItem>\n"
        << "        </Topology>\n        <Geometry GeometryType=\"XYZ\">\n";
      data_item(x, h5, frame + field_name::kPosition, p, 3, false);
      x << "        </Geometry>\n";
      std::vector<Array> all = {{field_name::kPosition, "", 3, false}};
      all.insert(all.end(), arrays.begin(), arrays.end());
      all.push_back({field_name::kMaterial, std::string("/") + field_name::kMaterial, 1, true});
      all.push_back({field_name::kObject, std::string("/") + field_name::kObject, 1, true});
      for (const Array& a : all) {
        x << "        <Attribute Name=\"" << a.name << "\" AttributeType=\""
          << attribute_type(a.width) << "\" Center=\"Node\">\n";
        data_item(x, h5, a.dataset.empty() ? frame + a.name : a.dataset, p, a.width, a.index);
        x << "        </Attribute>\n";
      }
      x << "      </Grid>\n";
    }
    x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
    return x.str();
  }
};

XdmfSeriesWriter::XdmfSeriesWriter(std::string xdmf_path, std::string h5_path,
                                   std::vector<uint16_t> material, std::vector<uint16_t> object)
    : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.xdmf_path = std::move(xdmf_path);
  w.h5_path = std::move(h5_path);
  w.tmp = w.h5_path + ".tmp";
  w.material = std::move(material);
  w.object = std::move(object);
  const size_t p = w.material.size();
  if (p == 0 || w.object.size() != p)
    fail(w.h5_path, ": no particles, or arrays of different lengths");
  check_replaceable(w.xdmf_path);  // written last: refused before the frames are
  h5::QuietErrors quiet;
  w.file = Handle(h5::create_exclusive(w.tmp, w.h5_path), H5Fclose);
  w.registration = TempFileRegistration(w.tmp);
  w.created = true;
  std::vector<int64_t> connectivity(p);
  for (size_t i = 0; i < p; ++i) connectivity[i] = static_cast<int64_t>(i);
  write_dataset(w.file.get(), "/connectivity", H5T_STD_I64LE, H5T_NATIVE_INT64, {p, 1},
                connectivity.data(), w.tmp);
  for (const auto& [name, values] :
       {std::pair{field_name::kMaterial, &w.material}, std::pair{field_name::kObject, &w.object}})
    write_dataset(w.file.get(), std::string("/") + name, H5T_STD_U16LE, H5T_NATIVE_UINT16, {p},
                  values->data(), w.tmp);
}

XdmfSeriesWriter::~XdmfSeriesWriter() = default;

void XdmfSeriesWriter::add_frame(size_t run_frame, const RunFrame& f) {
  Impl& w = *impl_;
  if (w.finished) fail(w.h5_path, ": XdmfSeriesWriter::add_frame after finish()");
  const size_t p = w.material.size();
  if (f.x.size() != p)
    fail(w.h5_path, ": frame ", run_frame, " has ", f.x.size(), " particles, not ", p);
  const std::vector<FrameField> fields = frame_fields(f, w.material, w.object, w.h5_path);
  const std::string frame = "/frames/" + std::to_string(run_frame) + "/";
  h5::QuietErrors quiet;
  std::vector<double> x(3 * p);
  for (size_t i = 0; i < p; ++i)
    for (int a = 0; a < 3; ++a) x[3 * i + a] = f.x[i][a];
  write_dataset(w.file.get(), frame + field_name::kPosition, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                {p, 3}, x.data(), w.tmp);
  const bool first = w.steps.empty();
  for (const FrameField& field : fields) {
    if (field.index) continue;  // material and object: once, at the root
    std::vector<hsize_t> shape{p};
    if (field.components > 1) shape.push_back(static_cast<hsize_t>(field.components));
    write_dataset(w.file.get(), frame + field.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, shape,
                  field.values.data(), w.tmp);
    if (first) w.arrays.push_back({field.name, "", field.components, false});
  }
  w.steps.emplace_back(run_frame, f.time);
}

void XdmfSeriesWriter::finish() {
  Impl& w = *impl_;
  if (w.finished) fail(w.h5_path, ": XdmfSeriesWriter::finish twice");
  {
    h5::QuietErrors quiet;
    if (!w.file.reset()) h5::fail(w.tmp, "closing the file failed (disk full?)");
  }
  // An XDMF file left by an earlier export of this run would describe the new HDF5 file's frames
  // wrongly until the new one replaces it: none is better.
  std::error_code ec;
  fs::remove(w.xdmf_path, ec);
  fs::rename(w.tmp, w.h5_path, ec);
  if (ec) fail(w.h5_path, ": cannot move ", w.tmp, " into place: ", ec.message());
  w.registration.release();
  w.finished = true;
  write_file_atomic(w.xdmf_path, w.xdmf());
}

}  // namespace nsf
