#include "core/json_parse.h"

#include <vector>

#include "core/error.h"
#include "core/json_util.h"

namespace nsf::json {

namespace {

using nlohmann::json;

// The key path of the value being parsed ("objects[0].material.E"), followed through the parse
// callback's events, so that an error the parser throws mid-value can name where it was.
class PathTracker {
 public:
  void event(json::parse_event_t event, const json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        open_.push_back({event == json::parse_event_t::array_start, "", 0});
        break;
      case json::parse_event_t::key:
        if (!open_.empty() && parsed.is_string()) open_.back().key = parsed.get<std::string>();
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!open_.empty()) open_.pop_back();
        next_element();
        break;
      case json::parse_event_t::value:
        next_element();
        break;
    }
  }

  std::string path() const {
    std::string p;
    for (const Level& l : open_) p = l.is_array ? child(p, l.index) : child(p, l.key);
    return p;
  }

 private:
  struct Level {
    bool is_array;
    std::string key;
    size_t index;
  };
  void next_element() {
    if (!open_.empty() && open_.back().is_array) ++open_.back().index;
  }
  std::vector<Level> open_;
};

// "[json.exception.out_of_range.406] number overflow parsing '1e999'" -> "1e999".
std::string quoted_part(const std::string& what) {
  const size_t open = what.find('\'');
  const size_t close = what.rfind('\'');
  return open == std::string::npos || close <= open ? what
                                                    : what.substr(open + 1, close - open - 1);
}

}  // namespace

nlohmann::json parse_bounded(const std::string& text, const std::string& what,
                             bool ignore_comments) {
  PathTracker at;
  // The callback sees each object and array as it opens, with the number of enclosing ones, so a
  // hostile text is stopped at the limit rather than built in full first.
  const json::parser_callback_t limit = [&what, &at](int depth, json::parse_event_t event,
                                                     json& parsed) {
    const bool opens =
        event == json::parse_event_t::object_start || event == json::parse_event_t::array_start;
    if (opens && depth >= kMaxJsonDepth)
      fail(what, " nests objects and arrays more than ", kMaxJsonDepth,
           " levels deep, which nsf does not accept (real scenes need fewer than 20)");
    at.event(event, parsed);
    return true;
  };
  try {
    return json::parse(text, limit, /*allow_exceptions=*/true, ignore_comments);
  } catch (const json::out_of_range& e) {
    // 406: a number literal beyond what a double holds (1e999); nlohmann's own message names
    // neither the file nor the key.
    if (e.id != 406) throw;
    const std::string where = at.path();
    fail(what, ": the number ", quoted_part(e.what()), where.empty() ? "" : " at '" + where + "'",
         " is out of range (a double holds at most about 1.8e308)");
  }
}

nlohmann::json parse_bounded_or_discarded(const std::string& text, const std::string& what) {
  try {
    return parse_bounded(text, what, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error&) {
    return nlohmann::json(nlohmann::json::value_t::discarded);
  }
}

bool nested_deeper_than(const json& value, int limit) {
  std::vector<std::pair<const json*, int>> todo{{&value, 0}};
  while (!todo.empty()) {
    const auto [v, depth] = todo.back();
    todo.pop_back();
    if (!v->is_structured()) continue;
    if (depth + 1 > limit) return true;
    for (const json& child : *v) todo.emplace_back(&child, depth + 1);
  }
  return false;
}

}  // namespace nsf::json
