// The model file (docs/TRAINING.md, "Model file"): NeuralModel's archive form over its format
// versions, and its atomic, checksummed save and load (nn/model/neural_model.h).
#include "nn/model/neural_model.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"
#include "nn/basis_export.h"
#include "nn/checked_archive.h"
#include "nn/model/model_file_checks.h"

namespace nsf {

namespace {

constexpr const char* kFormat = "nsf-model";
// 2: g predicts x − X (displacement, norm_u). 3: encoder_max_length, which an older nsf would
// ignore and then fail on the encoder's parameters, so it refuses the file instead.
constexpr int64_t kFormatVersion = 3;
// 4: a basis model (per-point bases and coefficient networks instead of g, h, l), which an older
// nsf must refuse. MLP models keep writing 3.
constexpr int64_t kBasisFormatVersion = 4;
// 5: a basis model whose τ and C coefficients are maps (nn/rbf_map.h), which an older nsf would
// take for its untrained networks: it refuses the file.
constexpr int64_t kMapFormatVersion = 5;
// 6: a basis model whose encoder is the projection on its leading modes (`encoder_kind` = modes),
// which an older nsf would take for its untrained convolutions: it refuses the file.
constexpr int64_t kModesEncoderFormatVersion = 6;
// 7: a basis model whose τ map reads the latent velocity (`stress_uses_velocity`), which an older
// nsf would call with too few inputs: it refuses the file.
constexpr int64_t kStressVelocityFormatVersion = 7;
// 8: a basis model whose bases' means and modes are stored once, in its run-time record
// (`runtime_record`, nn/model_record.h), which an older nsf would not find: it refuses the file.
constexpr int64_t kRecordFormatVersion = 8;
// 9: the other layers' records in `attachments` (the ROM's calibration among them, which 1-8
// stored in entries of their own: an older nsf would run the model uncalibrated), and a basis
// model's run-time record of version 2 (nn/model_record.cpp), which holds them too. Every basis
// model (its bases in its record, as in 8) and an MLP model with attachments.
constexpr int64_t kAttachmentsFormatVersion = 9;
constexpr int64_t kNewestFormatVersion = kAttachmentsFormatVersion;
// nsf has stored a checksum in every model file since before format version 5 was written, so a
// file of version 5 or later without one was changed after nsf wrote it (bytes appended or cut,
// the zip comment removed). Files of versions 3 and 4 written since carry the entry
// `checksummed`, which says the same of them; older ones load with a note.
constexpr int64_t kFirstChecksummedFormatVersion = 5;
constexpr const char* kMapParts[5] = {"centers", "weights", "poly", "shift", "scale"};
constexpr const char* kBasisNames[3] = {"u", "tau", "C"};
constexpr const char* kRecordEntry = "runtime_record";
constexpr const char* kAttachmentsEntry = "attachments";
constexpr int64_t kBasisDims[3] = {3, 6, 9};

void write_normalizer(torch::serialize::OutputArchive& a, const std::string& name,
                      const Normalizer& n) {
  a.write("norm_" + name + "_mean", n.mean, /*is_buffer=*/true);
  a.write("norm_" + name + "_std", n.std, /*is_buffer=*/true);
}

Normalizer read_normalizer(torch::serialize::InputArchive& a, const std::string& name, int64_t dim,
                           const std::string& path) {
  Normalizer n;
  a.read("norm_" + name + "_mean", n.mean, /*is_buffer=*/true);
  a.read("norm_" + name + "_std", n.std, /*is_buffer=*/true);
  check_model_tensor(n.mean, {dim}, "norm_" + name + "_mean", path);
  check_model_tensor(n.std, {dim}, "norm_" + name + "_std", path);
  if (!(n.std > 0).all().item<bool>())
    fail("model file ", path, ": entry 'norm_", name, "_std' holds a scale that is not positive");
  return n;
}

// The other layers' records (ModelAttachments): one JSON object, name -> text.
void write_attachments(torch::serialize::OutputArchive& a, const ModelAttachments& attachments) {
  if (!attachments.empty())
    a.write(kAttachmentsEntry, c10::IValue(nlohmann::json(attachments).dump()));
}

ModelAttachments read_attachments(torch::serialize::InputArchive& a, const std::string& path) {
  ModelAttachments attachments;
  c10::IValue entry;
  if (!a.try_read(kAttachmentsEntry, entry)) return attachments;
  const nlohmann::json j = entry.isString()
                               ? nlohmann::json::parse(entry.toStringRef(), nullptr, false)
                               : nlohmann::json();
  if (!j.is_object()) fail("model file ", path, ": damaged entry '", kAttachmentsEntry, "'");
  for (const auto& [name, text] : j.items()) {
    if (!text.is_string())
      fail("model file ", path, ": damaged entry '", kAttachmentsEntry, "' (", name,
           " is not text)");
    attachments[name] = text.get<std::string>();
  }
  return attachments;
}

// Format versions 1-8 stored the ROM's calibration (`nsf calibrate`) in entries of their own,
// "" for the decoded stress's and "tracked_" for the tracked state's (docs/TRAINING.md). Checked
// as those versions' reader checked them, they become the attachment they now belong to, by the
// same names (adopt_legacy_entries), so that an old model keeps its calibration.
void read_legacy_entries(torch::serialize::InputArchive& a, const std::string& path,
                         ModelAttachments& attachments) {
  nlohmann::json entries = nlohmann::json::object();
  for (const std::string prefix : {"", "tracked_"}) {
    c10::IValue prior, table, ratio;
    if (a.try_read(prefix + "latent_prior", prior)) {
      if (!prior.isDouble() || !std::isfinite(prior.toDouble()) || prior.toDouble() < 0 ||
          !a.try_read(prefix + "latent_prior_calibration", table) || !table.isString())
        fail("model file ", path, ": damaged entry '", prefix, "latent_prior'");
      const nlohmann::json t = nlohmann::json::parse(table.toStringRef(), nullptr, false);
      if (t.is_discarded())
        fail("model file ", path, ": damaged entry '", prefix, "latent_prior_calibration'");
      entries[prefix + "latent_prior"] = prior.toDouble();
      entries[prefix + "latent_prior_calibration"] = t;
    }
    if (a.try_read(prefix + "calibrated_dt_ratio", ratio)) {
      if (!ratio.isDouble() || !std::isfinite(ratio.toDouble()) || ratio.toDouble() <= 0)
        fail("model file ", path, ": damaged entry '", prefix, "calibrated_dt_ratio'");
      entries[prefix + "calibrated_dt_ratio"] = ratio.toDouble();
    }
  }
  adopt_legacy_entries(attachments, entries);
}

c10::IValue read_value(torch::serialize::InputArchive& a, const std::string& key,
                       const std::string& path) {
  c10::IValue v;
  if (!a.try_read(key, v)) fail("model file ", path, ": missing entry '", key, "'");
  return v;
}

}  // namespace

void NeuralModel::write(torch::serialize::OutputArchive& a, bool bases_in_record) const {
  a.write("format", c10::IValue(std::string(kFormat)));
  const int64_t version = bases_in_record || (!is_basis() && !attachments.empty())
                              ? kAttachmentsFormatVersion
                          : config.stress_reads_velocity() ? kStressVelocityFormatVersion
                          : config.encoder == "modes"      ? kModesEncoderFormatVersion
                          : config.uses_maps()             ? kMapFormatVersion
                          : is_basis()                     ? kBasisFormatVersion
                                                           : kFormatVersion;
  a.write("format_version", c10::IValue(version));
  a.write("nsf_version", c10::IValue(std::string(NSF_VERSION)));
  a.write("checksummed", c10::IValue(true));
  a.write("scene_name", c10::IValue(scene.scene_name));
  a.write("scene_particles", c10::IValue(scene.particles));
  a.write("scene_x_hash", c10::IValue(hex64(scene.x_hash)));
  a.write("latent_dim", c10::IValue(int64_t(config.latent_dim)));
  a.write("depth", c10::IValue(int64_t(config.depth)));
  a.write("width_g", c10::IValue(int64_t(config.width_g)));
  a.write("width_h", c10::IValue(int64_t(config.width_h)));
  a.write("width_l", c10::IValue(int64_t(config.width_l)));
  a.write("encoder_hidden", c10::IValue(int64_t(config.encoder_hidden)));
  a.write("encoder_channels", c10::IValue(int64_t(config.encoder_channels)));
  a.write("encoder_max_length", c10::IValue(int64_t(config.encoder_max_length)));
  a.write("stress_uses_mu", c10::IValue(config.stress_uses_mu));
  a.write("has_mu", c10::IValue(has_mu));
  a.write("mu_min", c10::IValue(mu_min));
  a.write("mu_max", c10::IValue(mu_max));
  a.write("train_seconds", c10::IValue(train_seconds));
  a.write("training_box", c10::IValue(training_box.to_json().dump()));
  write_attachments(a, attachments);
  write_normalizer(a, "X", norm_X);
  write_normalizer(a, "x", norm_x);
  write_normalizer(a, "z", norm_z);
  write_normalizer(a, "mu", norm_mu);
  write_normalizer(a, "tau", norm_tau);
  write_normalizer(a, "C", norm_C);
  a.write("displacement", c10::IValue(displacement));
  write_normalizer(a, "u", norm_u);
  if (displacement) a.write("rest", rest, /*is_buffer=*/true);
  if (trajectory_latents.defined()) {
    a.write("trajectory_latents", trajectory_latents, /*is_buffer=*/true);
    a.write("trajectory_mu", trajectory_mu, /*is_buffer=*/true);
  }
  std::vector<std::pair<std::string, const torch::nn::Module*>> nets = {{"encoder", encoder.get()}};
  if (is_basis()) {
    a.write("decoder", c10::IValue(std::string(family_name(config.decoder))));
    a.write("coefficient_width", c10::IValue(int64_t(config.coefficient_width)));
    a.write("coefficient_depth", c10::IValue(int64_t(config.coefficient_depth)));
    // Each entry from the format version that introduced it on: versions 8 and 9 have them all.
    if (bases_in_record || config.encoder == "modes" || config.stress_reads_velocity())
      a.write("encoder_kind", c10::IValue(config.encoder));
    if (bases_in_record || config.uses_maps()) {
      a.write("coefficients_tau", c10::IValue(config.coefficients[0]));
      a.write("coefficients_C", c10::IValue(config.coefficients[1]));
      a.write("affine_uses_velocity", c10::IValue(config.affine_uses_velocity));
    }
    if (bases_in_record || config.stress_reads_velocity())
      a.write("stress_uses_velocity", c10::IValue(config.stress_reads_velocity()));
    for (int f = 0; f < 3; ++f) {
      const std::string n = kBasisNames[f];
      a.write("modes_" + n, c10::IValue(int64_t(config.modes[f])));
      if (!bases_in_record) {
        a.write("basis_" + n + "_mean", basis[f].mean, /*is_buffer=*/true);
        a.write("basis_" + n + "_modes", basis[f].modes, /*is_buffer=*/true);
      }
      a.write("basis_" + n + "_scale", basis[f].scale, /*is_buffer=*/true);
      if (basis[f].has_map()) {
        const torch::Tensor* parts[5] = {&basis[f].map_centers, &basis[f].map_weights,
                                         &basis[f].map_poly, &basis[f].map_shift,
                                         &basis[f].map_scale};
        for (int k = 0; k < 5; ++k)
          a.write("map_" + n + "_" + kMapParts[k], *parts[k], /*is_buffer=*/true);
      }
      nets.emplace_back("c_" + n, basis[f].net.get());
    }
  } else {
    // Versions 4-8 are basis models alone; from 9 on, an MLP model names its family too.
    if (version >= kAttachmentsFormatVersion)
      a.write("decoder", c10::IValue(std::string(family_name(config.decoder))));
    nets.insert(nets.end(), {{"g", g.get()}, {"h", h.get()}, {"l", l.get()}});
  }
  for (const auto& [name, net] : nets) {
    torch::serialize::OutputArchive sub;
    net->save(sub);
    a.write(name, sub);
  }
}

namespace {

// A coefficient map's entries, absent from a checkpoint written before its stage ran; present,
// they must agree with each other and hold finite float64 values.
void read_map(torch::serialize::InputArchive& a, BasisField& b, const std::string& n,
              const std::string& path) {
  torch::Tensor* parts[5] = {&b.map_centers, &b.map_weights, &b.map_poly, &b.map_shift,
                             &b.map_scale};
  int present = 0;
  for (int k = 0; k < 5; ++k)
    present += a.try_read("map_" + n + "_" + kMapParts[k], *parts[k], /*is_buffer=*/true);
  if (present == 0) {
    for (torch::Tensor* t : parts) *t = torch::Tensor();
    return;
  }
  const auto bad = [&](const std::string& why) {
    fail("model file ", path, ": damaged coefficient map of ", n, " (", why, ")");
  };
  if (present != 5) bad("entries missing");
  for (torch::Tensor* t : parts)
    if (t->scalar_type() != torch::kFloat64 || !torch::isfinite(*t).all().item<bool>())
      bad("not finite float64 values");
  const int64_t N = b.map_centers.size(0),
                d = b.map_centers.dim() == 2 ? b.map_centers.size(1) : -1;
  if (b.map_centers.dim() != 2 || b.map_weights.sizes() != torch::IntArrayRef({N, b.K()}) ||
      b.map_poly.sizes() != torch::IntArrayRef({d + 1, b.K()}) ||
      b.map_shift.sizes() != torch::IntArrayRef({d}) ||
      b.map_scale.sizes() != torch::IntArrayRef({d}) || N < d + 2)
    bad("shapes disagree");
}

}  // namespace

NeuralModel NeuralModel::read(torch::serialize::InputArchive& a, const std::string& path) {
  c10::IValue format;
  if (!a.try_read("format", format) || !format.isString() || format.toStringRef() != kFormat)
    fail(path, " is not an nsf model file (no 'format' = '", kFormat, "' entry)");
  const int64_t version = read_value(a, "format_version", path).toInt();
  if (version > kNewestFormatVersion)
    fail("model file ", path, " has format version ", version, "; this nsf reads up to ",
         kNewestFormatVersion, " (written by nsf ",
         read_value(a, "nsf_version", path).toStringRef(), ")");
  auto integer = [&](const char* key) {
    return model_size_entry(read_value(a, key, path).toInt(), key, path);
  };
  NetConfig c;
  c.latent_dim = integer("latent_dim");
  c.depth = integer("depth");
  c.width_g = integer("width_g");
  c.width_h = integer("width_h");
  c.width_l = integer("width_l");
  c.encoder_hidden = integer("encoder_hidden");
  c10::IValue channels;  // absent before the option existed: App. E's 3
  if (a.try_read("encoder_channels", channels))
    c.encoder_channels = model_size_entry(channels.toInt(), "encoder_channels", path);
  c10::IValue max_length;  // absent before format version 3: App. E's 12
  if (a.try_read("encoder_max_length", max_length))
    c.encoder_max_length = model_size_entry(max_length.toInt(), "encoder_max_length", path);
  c.stress_uses_mu = read_value(a, "stress_uses_mu", path).toBool();
  c.decoder = DecoderFamily::mlp;  // the only family before format version 4
  if (version >= kBasisFormatVersion)
    c.decoder = parse_family(read_value(a, "decoder", path).toStringRef(),
                             "model file " + path + ": damaged entry 'decoder'");
  // Versions 4-8 are basis models alone; from 9 on, an MLP model names its family too.
  if (version >= kBasisFormatVersion &&
      (version < kAttachmentsFormatVersion || c.decoder == DecoderFamily::basis)) {
    c.coefficient_width = integer("coefficient_width");
    c.coefficient_depth = integer("coefficient_depth");
    for (int f = 0; f < 3; ++f)
      c.modes[f] = integer((std::string("modes_") + kBasisNames[f]).c_str());
    c.coefficients = {"network", "network"};  // the only kind before format version 5
    c.affine_uses_velocity = false;
    if (version >= kMapFormatVersion) {
      for (int f = 0; f < 2; ++f) {
        const std::string key = std::string("coefficients_") + kBasisNames[f + 1];
        c.coefficients[size_t(f)] = read_value(a, key.c_str(), path).toStringRef();
        if (c.coefficients[size_t(f)] != "map" && c.coefficients[size_t(f)] != "network")
          fail("model file ", path, ": damaged entry '", key, "' ('", c.coefficients[size_t(f)],
               "'; known: map, network)");
      }
      c.affine_uses_velocity = read_value(a, "affine_uses_velocity", path).toBool();
    }
    if (version >= kModesEncoderFormatVersion) {
      c.encoder = read_value(a, "encoder_kind", path).toStringRef();
      if (c.encoder != "modes" && c.encoder != "network")
        fail("model file ", path, ": damaged entry 'encoder_kind' ('", c.encoder,
             "'; known: modes, network)");
    }
    c.stress_uses_velocity = version >= kStressVelocityFormatVersion &&
                             read_value(a, "stress_uses_velocity", path).toBool();
    if (c.stress_uses_velocity && !c.stress_reads_velocity())
      fail("model file ", path,
           ": damaged entry 'stress_uses_velocity' (set, but tau's coefficients are no map)");
  }
  SceneFingerprint s;
  s.scene_name = read_value(a, "scene_name", path).toStringRef();
  s.particles =
      model_size_entry(read_value(a, "scene_particles", path).toInt(), "scene_particles", path);
  s.x_hash = model_hash_entry(read_value(a, "scene_x_hash", path).toStringRef(), path);
  const bool has_mu = read_value(a, "has_mu", path).toBool();
  std::error_code ec;
  const uintmax_t bytes = std::filesystem::file_size(path, ec);
  check_model_fits_file(c, s.particles, has_mu && c.stress_uses_mu, ec ? 0 : bytes, path);
  NeuralModel m(c, s, has_mu);
  m.mu_min = read_value(a, "mu_min", path).toDouble();
  m.mu_max = read_value(a, "mu_max", path).toDouble();
  c10::IValue seconds;  // absent before nsf recorded it
  if (a.try_read("train_seconds", seconds)) m.train_seconds = seconds.toDouble();
  c10::IValue box;  // absent before nsf recorded it
  if (a.try_read("training_box", box)) {
    if (!box.isString()) fail("model file ", path, ": damaged entry 'training_box' (not text)");
    const nlohmann::json j = nlohmann::json::parse(box.toStringRef(), nullptr, false);
    if (j.is_discarded()) fail("model file ", path, ": damaged entry 'training_box' (not JSON)");
    m.training_box = TrainingBox::from_json(j, "model file " + path + ": entry 'training_box'");
  }
  m.attachments = read_attachments(a, path);
  read_legacy_entries(a, path, m.attachments);
  m.norm_X = read_normalizer(a, "X", 3, path);
  m.norm_x = read_normalizer(a, "x", 3, path);
  m.norm_z = read_normalizer(a, "z", c.latent_dim, path);
  m.norm_mu = read_normalizer(a, "mu", 1, path);
  m.norm_tau = read_normalizer(a, "tau", 6, path);
  m.norm_C = read_normalizer(a, "C", 9, path);
  c10::IValue residual;
  m.displacement = version >= 2 && a.try_read("displacement", residual) && residual.toBool();
  if (m.is_basis() && !m.displacement)
    fail("model file ", path,
         ": damaged entry 'displacement' (false, but a basis model is always in displacement "
         "form and stores its rest positions)");
  if (m.displacement) {
    m.norm_u = read_normalizer(a, "u", 3, path);
    a.read("rest", m.rest, /*is_buffer=*/true);
    check_model_tensor(m.rest, {s.particles, 3}, "rest", path);
  }
  // Absent from models written before the latent prior existed (format version 3 all the same:
  // an older nsf reads these files and ignores the entries).
  torch::Tensor trajectories, trajectory_mu;
  if (a.try_read("trajectory_latents", trajectories, /*is_buffer=*/true) &&
      a.try_read("trajectory_mu", trajectory_mu, /*is_buffer=*/true)) {
    if (trajectories.dim() != 3 || trajectories.size(2) != c.latent_dim ||
        trajectory_mu.dim() != 1 || trajectory_mu.size(0) != trajectories.size(0) ||
        trajectories.scalar_type() != torch::kFloat32 ||
        trajectory_mu.scalar_type() != torch::kFloat32 ||
        !torch::isfinite(trajectories).all().item<bool>() ||
        !torch::isfinite(trajectory_mu).all().item<bool>())
      fail("model file ", path, ": damaged training latents (shape ", trajectories.sizes(), ")");
    m.trajectory_latents = trajectories;
    m.trajectory_mu = trajectory_mu;
  }
  torch::Tensor record;
  if (a.try_read(kRecordEntry, record, /*is_buffer=*/true)) {
    if (record.scalar_type() != torch::kUInt8 || record.dim() != 1)
      fail("model file ", path, ": its run-time record is not a byte array");
    record = record.contiguous();
    m.stored_record = std::make_shared<const ModelRecord>(decode_model_record(
        std::string_view(reinterpret_cast<const char*>(record.data_ptr<uint8_t>()),
                         size_t(record.numel())),
        path));
  }
  if (m.stored_record &&
      (!m.stored_record->scene.matches(s) || m.stored_record->latent_dim != c.latent_dim ||
       m.stored_record->family != c.decoder))
    fail("model file ", path, ": its run-time record is another model's (",
         m.stored_record->scene.describe(), ")");
  // Version 8 is only a basis model's; 9 either family's, a basis model's bases in its record.
  if (version >= kRecordFormatVersion && (m.is_basis() || version == kRecordFormatVersion) &&
      !(m.is_basis() && m.stored_record && m.stored_record->bases))
    fail("model file ", path, ": a basis model of format version ", version,
         " keeps its bases in its run-time record, and it has none");
  std::vector<std::pair<std::string, torch::nn::Module*>> nets = {{"encoder", m.encoder.get()}};
  if (m.is_basis()) {
    for (int f = 0; f < 3; ++f) {
      const std::string n = kBasisNames[f];
      BasisField& b = m.basis[f];
      if (version >= kRecordFormatVersion) {
        const BasisDecoders& d = *m.stored_record->bases;
        const PointBasis& pb = f == 0 ? d.u : f == 1 ? d.tau : d.C;
        b.mean = torch::from_blob(const_cast<float*>(pb.mean.data()),
                                  {int64_t(pb.points), int64_t(pb.dim)}, torch::kFloat32)
                     .clone();
        b.modes =
            torch::from_blob(const_cast<float*>(pb.modes.data()),
                             {int64_t(pb.points), int64_t(pb.dim), int64_t(pb.K)}, torch::kFloat32)
                .clone();
      } else {
        a.read("basis_" + n + "_mean", b.mean, /*is_buffer=*/true);
        a.read("basis_" + n + "_modes", b.modes, /*is_buffer=*/true);
      }
      a.read("basis_" + n + "_scale", b.scale, /*is_buffer=*/true);
      const int64_t K = c.modes[f], d = kBasisDims[f];
      if (b.mean.sizes() != torch::IntArrayRef({s.particles, d}) ||
          b.modes.sizes() != torch::IntArrayRef({s.particles, d, K}) ||
          b.scale.sizes() != torch::IntArrayRef({K}))
        fail("model file ", path, ": damaged basis of ", n, " (shapes ", b.mean.sizes(), ", ",
             b.modes.sizes(), ", ", b.scale.sizes(), " for ", s.particles, " particles and K = ", K,
             ")");
      check_model_tensor(b.mean, {s.particles, d}, "basis_" + n + "_mean", path);
      check_model_tensor(b.modes, {s.particles, d, K}, "basis_" + n + "_modes", path);
      check_model_tensor(b.scale, {K}, "basis_" + n + "_scale", path);
      if (c.uses_map(f)) read_map(a, b, n, path);
      nets.emplace_back("c_" + n, b.net.get());
    }
  } else {
    nets.insert(nets.end(), {{"g", m.g.get()}, {"h", m.h.get()}, {"l", m.l.get()}});
  }
  for (const auto& [name, net] : nets) {
    torch::serialize::InputArchive sub;
    a.read(name, sub);
    load_network_checked(*net, sub, name, path);
  }
  return m;
}

void NeuralModel::save(const std::string& path) const {
  torch::serialize::OutputArchive a;
  try {
    // A basis model's run-time record, for the torch-free runtime: stored as a tensor, it is one
    // uncompressed zip entry whose first bytes name it (nn/model_record.h). It holds the bases,
    // which the archive then leaves out.
    write(a, /*bases_in_record=*/is_basis());
    if (is_basis()) {
      std::string bytes = encode_model_record(model_record(*this));
      a.write(kRecordEntry,
              torch::from_blob(bytes.data(), {int64_t(bytes.size())}, torch::kUInt8).clone(),
              /*is_buffer=*/true);
    }
  } catch (const c10::Error& e) {
    fail("cannot write model ", path, ": ", e.what_without_backtrace());
  }
  save_checked_archive(a, path, "model file");  // atomic, with a checksum
}

NeuralModel NeuralModel::load(const std::string& path) {
  if (const std::string kind = non_regular_kind(path); !kind.empty())
    fail("model file ", path, " is not a regular file (it is ", kind, ")");
  if (!std::filesystem::is_regular_file(path)) fail("model file ", path, " does not exist");
  torch::serialize::InputArchive a;
  const bool checked = load_checked_archive(a, path, "model file");
  try {
    if (!checked) {
      c10::IValue version, marked;
      const bool written_with_checksum =
          (a.try_read("format_version", version) && version.isInt() &&
           version.toInt() >= kFirstChecksummedFormatVersion) ||
          (a.try_read("checksummed", marked) && marked.isBool() && marked.toBool());
      if (written_with_checksum)
        fail("model file ", path,
             " is damaged: nsf wrote it with a checksum, and it has none now (bytes were "
             "appended or cut, or its zip comment was removed). Copy it again or retrain");
      std::fprintf(stderr,
                   "nsf: note: model file %s has no checksum (written before nsf stored one); "
                   "its contents are not verified\n",
                   path.c_str());
    }
    NeuralModel m = read(a, path);
    m.set_eval_mode();
    return m;
  } catch (const Error&) {
    throw;
  } catch (const c10::Error& e) {
    fail("cannot read model ", path,
         " (not an nsf model, or damaged): ", e.what_without_backtrace());
  } catch (const std::exception& e) {  // torch's TorchScript reader throws its own types
    fail("cannot read model ", path, " (not an nsf model, or damaged): ", e.what());
  }
}

}  // namespace nsf
