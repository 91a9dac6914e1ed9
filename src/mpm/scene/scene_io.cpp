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

}  // namespace

nlohmann::json read_scene_json(const std::string& path, const std::vector<std::string>& overrides) {
  // A directory opens as a stream that reads nothing, which would come out as "not valid JSON".
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    fail("scene file '", path, "' is a directory, not a JSON file");
  // A regular file or a pipe, at most 64 MiB (core/input_file.h): not /dev/zero read to the end.
  const std::string text = read_input_file(path, "scene file");

  nlohmann::json j;
  try {
    // Comments are allowed so example scenes can explain themselves.
    j = json::parse_bounded(text, "scene file '" + path + "'", /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is one past the offending character.
    fail("scene file '", path, "' is not valid JSON at ",
         line_column(text, e.byte ? e.byte - 1 : 0), ": ", parse_detail(e.what()));
  }
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
