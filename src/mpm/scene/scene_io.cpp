#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "core/input_file.h"
#include "core/json_parse.h"
#include "mpm/scene/scene.h"

namespace nsf {
namespace {

// nlohmann reports a byte offset; people edit by line and column.
std::string line_column(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

// Drops nlohmann's "[json.exception...] parse error at line L, column C: " prefix, which would
// repeat the position.
std::string parse_detail(const std::string& what) {
  size_t col = what.find("column ");
  size_t colon = col == std::string::npos ? col : what.find(": ", col);
  return colon == std::string::npos ? what : what.substr(colon + 2);
}

// How many scene files one may extend in a chain (a extends b extends c ...).
constexpr size_t kMaxExtends = 8;

// The file's JSON as written (comments allowed, so example scenes can explain themselves).
nlohmann::json parse_scene_text(const std::string& path) {
  // A directory opens as a stream that reads nothing, which would come out as "not valid JSON".
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    fail("scene file '", path, "' is a directory, not a JSON file");
  // A regular file or a pipe, at most 64 MiB (core/input_file.h): not /dev/zero read to the end.
  const std::string text = read_input_file(path, "scene file");
  try {
    return json::parse_bounded(text, "scene file '" + path + "'", /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is one past the offending character.
    fail("scene file '", path, "' is not valid JSON at ",
         line_column(text, e.byte ? e.byte - 1 : 0), ": ", parse_detail(e.what()));
  }
}

// The file's JSON with the scene it "extends" under it: that file (relative to this one's
// directory) read the same way, with this file's keys merged over it (RFC 7386: an object key by
// key, any other value replaced, null removes the key). The name is this file's own, never the
// base's. `chain` holds the files already on the way, to refuse a cycle.
nlohmann::json scene_with_base(const std::string& path, std::vector<std::string>& chain) {
  nlohmann::json j = parse_scene_text(path);
  if (!j.is_object() || !j.contains("extends")) return j;
  const nlohmann::json& e = j.at("extends");
  if (!e.is_string() || e.get<std::string>().empty())
    fail("scene file '", path,
         "': 'extends' must be the path of the scene file it extends (relative to this one), got ",
         e.dump());
  namespace fs = std::filesystem;
  const fs::path base = fs::path(path).parent_path() / e.get<std::string>();
  std::error_code ec;
  const std::string key = fs::weakly_canonical(base, ec).string();
  for (const std::string& seen : chain)
    if (seen == key) fail("scene file '", path, "' extends ", base.string(), ", which extends it");
  if (chain.size() >= kMaxExtends)
    fail("scene file '", path, "': more than ", kMaxExtends, " scene files extend one another");
  // A regular file only: a pipe named inside a scene could hold its reader forever.
  if (fs::exists(base, ec) && !fs::is_regular_file(base, ec))
    fail("scene file '", path, "' extends ", base.string(), ", which is not a regular file");
  chain.push_back(key);
  nlohmann::json merged;
  try {
    merged = scene_with_base(base.string(), chain);
  } catch (const Error& err) {
    fail("scene file '", path, "' extends '", e.get<std::string>(), "': ", err.what());
  }
  if (!merged.is_object())
    fail("scene file '", path, "' extends ", base.string(), ", which is not a JSON object");
  merged.erase("name");
  j.erase("extends");
  merged.merge_patch(j);
  return merged;
}

}  // namespace

nlohmann::json read_scene_json(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  std::vector<std::string> chain = {std::filesystem::weakly_canonical(path, ec).string()};
  nlohmann::json j = scene_with_base(path, chain);
  try {
    apply_overrides(j, overrides);
  } catch (const Error& e) {
    fail(path, ": ", e.what());
  }
  if (j.is_object() && !j.contains("name")) j["name"] = std::filesystem::path(path).stem().string();
  return j;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  const nlohmann::json j = read_scene_json(path, overrides);
  try {
    return build_scene(j, std::filesystem::path(path).parent_path().string());
  } catch (const Error& e) {
    fail(path, ": ", e.what());
  }
}

}  // namespace nsf
