#include "core/json_parse.h"

#include "core/error.h"

namespace nsf::json {

nlohmann::json parse_bounded(const std::string& text, const std::string& what,
                             bool ignore_comments) {
  using nlohmann::json;
  // The callback sees each object and array as it opens, with the number of enclosing ones, so a
  // hostile text is stopped at the limit rather than built in full first.
  const json::parser_callback_t limit = [&what](int depth, json::parse_event_t event, json&) {
    const bool opens =
        event == json::parse_event_t::object_start || event == json::parse_event_t::array_start;
    if (opens && depth >= kMaxJsonDepth)
      fail(what, " nests objects and arrays more than ", kMaxJsonDepth,
           " levels deep, which nsf does not accept (real scenes need fewer than 20)");
    return true;
  };
  return json::parse(text, limit, /*allow_exceptions=*/true, ignore_comments);
}

nlohmann::json parse_bounded_or_discarded(const std::string& text, const std::string& what) {
  try {
    return parse_bounded(text, what, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error&) {
    return nlohmann::json(nlohmann::json::value_t::discarded);
  }
}

}  // namespace nsf::json
