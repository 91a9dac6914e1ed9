#pragma once
// Structure-aware mutations of a JSON document for the fuzz tests (fuzz_harness.h): delete or
// duplicate a key, misspell one, swap a value's type, put extreme numbers (huge, tiny, negative,
// NaN, 1e999) or hostile strings in, empty or repeat arrays, nest a value thousands of levels
// deep. Mutations that JSON values cannot hold (duplicate keys, 1e999, deep nesting) are made in
// the text: the value carries a placeholder that `text()` replaces.
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

namespace nsf::testing::fuzz {

class JsonMutator {
 public:
  JsonMutator(nlohmann::json doc, std::mt19937_64& rng) : doc_(std::move(doc)), rng_(rng) {}

  // Applies one random mutation; returns what it did.
  std::string mutate() {
    std::vector<nlohmann::json::json_pointer> nodes;
    collect(doc_, nlohmann::json::json_pointer(), nodes);
    const nlohmann::json::json_pointer at = nodes[below(nodes.size())];
    nlohmann::json& v = doc_[at];
    const std::string where = at.to_string();
    switch (below(10)) {
      case 0:
        if (!at.empty()) {
          nlohmann::json& parent = doc_[at.parent_pointer()];
          if (parent.is_object()) {
            parent.erase(at.back());
          } else {
            parent.erase(std::stoul(at.back()));
          }
          return "deleted " + where;
        }
        [[fallthrough]];
      case 1:
        v = other_type(v);
        return "type swapped " + where;
      case 2:
        return number(v, where);
      case 3:
        v = hostile_string();
        return "hostile string at " + where;
      case 4:
        if (v.is_array() && !v.empty()) {
          const nlohmann::json first = v[below(v.size())];
          const size_t copies = 1 + below(40);
          for (size_t i = 0; i < copies; ++i) v.push_back(first);
          return "repeated an element of " + where + " " + std::to_string(copies) + " times";
        }
        if (v.is_array() || v.is_object()) {
          v = v.is_array() ? nlohmann::json::array() : nlohmann::json::object();
          return "emptied " + where;
        }
        return number(v, where);
      case 5: {
        const int depth = std::vector<int>{3, 60, 600, 20000}[below(4)];
        v = "\x01"
            "deep" +
            std::to_string(depth) + "\x01" + v.dump();
        return "nested " + where + " " + std::to_string(depth) + " deep";
      }
      case 6:
        if (v.is_object() && !v.empty()) {
          auto it = v.begin();
          std::advance(it, below(v.size()));
          duplicate_key_ = it.key();
          v["\x01"
            "dup"] = other_type(it.value());
          return "duplicated key " + where + "/" + it.key();
        }
        return number(v, where);
      case 7:
        if (v.is_object() && !v.empty()) {
          auto it = v.begin();
          std::advance(it, below(v.size()));
          std::string key = it.key();
          nlohmann::json value = it.value();
          v.erase(key);
          if (!key.empty()) key[below(key.size())] = 'q';
          v[key] = value;
          return "misspelt a key of " + where + " as " + key;
        }
        [[fallthrough]];
      case 8:
        if (v.is_object()) {
          v["unexpected"] = 1;
          return "added a key to " + where;
        }
        return number(v, where);
      default:
        return number(v, where);
    }
  }

  // The document as text, the placeholders replaced.
  std::string text() const {
    std::string t = doc_.dump();
    for (size_t at = t.find("\"\\u0001deep"); at != std::string::npos;
         at = t.find("\"\\u0001deep")) {
      const size_t digits = at + 11, end = t.find("\\u0001", digits);
      const int depth = std::stoi(t.substr(digits, end - digits));
      size_t close = end + 6;  // the placeholder's closing quote: skip escaped characters
      while (close < t.size() && t[close] != '"') close += t[close] == '\\' ? 2 : 1;
      const std::string inner =
          nlohmann::json::parse("\"" + t.substr(end + 6, close - end - 6) + "\"")
              .get<std::string>();
      t.replace(at, close + 1 - at, std::string(depth, '[') + inner + std::string(depth, ']'));
    }
    replace_all(t, "\"\\u0001dup\"", nlohmann::json(duplicate_key_).dump());
    for (const char* raw : {"1e999", "-1e999", "NaN", "Infinity", "1e-400", "-0", "1e308",
                            "18446744073709551616", "-9223372036854775809"})
      replace_all(t, "\"\\u0001num" + std::string(raw) + "\"", raw);
    return t;
  }

  const nlohmann::json& doc() const { return doc_; }

 private:
  size_t below(size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_);
  }

  static void replace_all(std::string& t, const std::string& from, const std::string& to) {
    for (size_t at = t.find(from); at != std::string::npos; at = t.find(from, at + to.size()))
      t.replace(at, from.size(), to);
  }

  static void collect(const nlohmann::json& v, const nlohmann::json::json_pointer& here,
                      std::vector<nlohmann::json::json_pointer>& out) {
    out.push_back(here);
    if (v.is_object()) {
      for (auto it = v.begin(); it != v.end(); ++it) collect(it.value(), here / it.key(), out);
    } else if (v.is_array()) {
      for (size_t i = 0; i < v.size(); ++i) collect(v[i], here / i, out);
    }
  }

  nlohmann::json other_type(const nlohmann::json& v) {
    const std::vector<nlohmann::json> kinds = {nullptr,
                                               true,
                                               -3,
                                               0.5,
                                               "text",
                                               nlohmann::json::array({1, 2, 3}),
                                               nlohmann::json::object({{"a", 1}}),
                                               nlohmann::json::array()};
    nlohmann::json pick = kinds[below(kinds.size())];
    while (pick.type() == v.type()) pick = kinds[below(kinds.size())];
    return pick;
  }

  std::string number(nlohmann::json& v, const std::string& where) {
    const double x = v.is_number() ? v.get<double>() : 1.0;
    switch (below(4)) {
      case 0: {
        const std::vector<std::string> raw = {"1e999",
                                              "-1e999",
                                              "NaN",
                                              "Infinity",
                                              "1e-400",
                                              "-0",
                                              "1e308",
                                              "18446744073709551616",
                                              "-9223372036854775809"};
        const std::string r = raw[below(raw.size())];
        v = "\x01num" + r;
        return where + " = " + r;
      }
      case 1: {
        const std::vector<double> extremes = {0.0,    -1.0,         1e300,  -1e300,
                                              5e-324, 2147483648.0, 9.3e18, -2147483649.0};
        v = extremes[below(extremes.size())];
        break;
      }
      case 2: {
        const std::vector<nlohmann::json> ints = {
            0, -1, 1, 2147483647, -2147483648LL, 4294967296LL, 9223372036854775807LL};
        v = ints[below(ints.size())];
        break;
      }
      default: {
        const std::vector<double> factors = {-1, 1e-6, 1e-3, 0.1, 10, 1e3, 1e6};
        v = x * factors[below(factors.size())];
        break;
      }
    }
    return where + " = " + v.dump();
  }

  nlohmann::json hostile_string() {
    const std::vector<std::string> s = {"",
                                        std::string(100000, 'a'),
                                        "/dev/zero",
                                        "/",
                                        "../../../../../../etc/passwd",
                                        "x'; system \"touch PWNED\"; #",
                                        "$(touch PWNED)",
                                        "%s%s%s%n",
                                        "\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80",
                                        "nan",
                                        "-1",
                                        "union",
                                        "mesh",
                                        "von_mises"};
    return s[below(s.size())];
  }

  nlohmann::json doc_;
  std::mt19937_64& rng_;
  std::string duplicate_key_;
};

}  // namespace nsf::testing::fuzz
