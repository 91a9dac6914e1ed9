#pragma once
// Parsing JSON text from files and the command line with a bound on its nesting. nlohmann parses
// and frees any depth without recursion, but copying, printing and comparing recurse, so a hostile
// scene nested 100,000 deep would overflow the stack there; real scenes nest fewer than 20 levels.
#include <nlohmann/json.hpp>
#include <string>

namespace nsf::json {

// The deepest nesting of objects and arrays a JSON text may have.
constexpr int kMaxJsonDepth = 512;

// nlohmann::json::parse that refuses texts nested deeper than kMaxJsonDepth with an nsf::Error
// naming `what` (e.g. "scene file 'a.json'") and the limit, and a number literal too large for a
// double (1e999) with one naming `what` and the key path of the number. Syntax errors stay
// nlohmann::json::parse_error, whose byte offset callers turn into a line and column.
nlohmann::json parse_bounded(const std::string& text, const std::string& what,
                             bool ignore_comments = false);

// True when a value (built in memory, past parse_bounded's check) nests objects and arrays more
// than `limit` levels deep. Iterative: nlohmann's copy and dump() recurse once per level, so a
// value must be checked before either (under AddressSanitizer 14,000 levels overflow the stack).
bool nested_deeper_than(const nlohmann::json& value, int limit);

// The same for readers that forgive a text that is not JSON (a run's stored scene, where it only
// adds detail to a picture): a discarded value for a syntax error, comments allowed; still an
// nsf::Error past the depth limit.
nlohmann::json parse_bounded_or_discarded(const std::string& text, const std::string& what);

}  // namespace nsf::json
