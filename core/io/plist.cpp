#include "io/plist.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "common/error.h"

namespace mpumesh::plist {
namespace {

class Parser {
 public:
  Parser(const std::string& s, const std::string& doc) : s_(s), doc_(doc) {}

  Value document() {
    size_t p = s_.find("<plist");
    if (p == std::string::npos) fail("no <plist> element");
    at_ = s_.find('>', p);
    if (at_ == std::string::npos) fail("unterminated <plist>");
    ++at_;
    return value(0);
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    throw InputError(doc_ + ": malformed property list: " + what);
  }
  void skip_space() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
  }
  // Reads the next tag name ("dict", "/dict", "true/"...).
  std::string tag() {
    skip_space();
    if (at_ >= s_.size() || s_[at_] != '<') fail("expected a tag");
    size_t end = s_.find('>', at_);
    if (end == std::string::npos) fail("unterminated tag");
    std::string t = s_.substr(at_ + 1, end - at_ - 1);
    at_ = end + 1;
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
    return t;
  }
  std::string text_until(const std::string& close) {
    size_t end = s_.find("</" + close + ">", at_);
    if (end == std::string::npos) fail("missing </" + close + ">");
    std::string t = unescape(s_.substr(at_, end - at_));
    at_ = end + close.size() + 3;
    return t;
  }
  static std::string unescape(const std::string& in) {
    std::string out;
    for (size_t i = 0; i < in.size(); ++i) {
      if (in[i] == '&') {
        static const std::pair<const char*, char> ents[] = {
            {"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
        bool hit = false;
        for (auto [e, c] : ents)
          if (in.compare(i, std::strlen(e), e) == 0) {
            out += c;
            i += std::strlen(e) - 1;
            hit = true;
            break;
          }
        if (!hit) out += in[i];
      } else {
        out += in[i];
      }
    }
    return out;
  }
  Value value(int depth) {
    if (depth > 64) fail("nesting too deep");
    const std::string t = tag();
    Value v;
    if (t == "dict") {
      v.type = Value::Type::kDict;
      for (;;) {
        std::string k = tag();
        if (k == "/dict") break;
        if (k == "dict/") fail("unexpected empty dict");
        if (k != "key") fail("expected <key> in <dict>, got <" + k + ">");
        std::string key = text_until("key");
        v.dict[key] = value(depth + 1);
      }
    } else if (t == "dict/") {
      v.type = Value::Type::kDict;
    } else if (t == "array") {
      v.type = Value::Type::kArray;
      for (;;) {
        size_t save = at_;
        if (tag() == "/array") break;
        at_ = save;
        v.array.push_back(value(depth + 1));
        if (v.array.size() > 1000000) fail("array too long");
      }
    } else if (t == "array/") {
      v.type = Value::Type::kArray;
    } else if (t == "string" || t == "integer" || t == "real") {
      v.text = text_until(t);
      v.type = t == "string" ? Value::Type::kString : t == "integer" ? Value::Type::kInteger : Value::Type::kReal;
      if (v.type != Value::Type::kString) {
        char* end = nullptr;
        v.number = std::strtod(v.text.c_str(), &end);
        if (end == v.text.c_str() || *end != '\0' || !std::isfinite(v.number))
          fail("<" + t + "> holds '" + v.text + "', not a number");
      }
    } else if (t == "string/") {
      v.type = Value::Type::kString;
    } else if (t == "true/" || t == "false/") {
      v.type = Value::Type::kBool;
      v.number = t == "true/" ? 1 : 0;
    } else {
      fail("unexpected <" + t + ">");
    }
    return v;
  }

  const std::string& s_;
  const std::string& doc_;
  size_t at_ = 0;
};

}  // namespace

const Value& Value::at(const std::string& key, const std::string& doc) const {
  if (type != Type::kDict) throw InputError(doc + ": expected a dictionary holding '" + key + "'");
  auto it = dict.find(key);
  if (it == dict.end()) throw InputError(doc + ": missing key '" + key + "'");
  return it->second;
}

double Value::as_number(const std::string& doc) const {
  if (type != Type::kInteger && type != Type::kReal) throw InputError(doc + ": expected a number");
  return number;
}

const std::string& Value::as_string(const std::string& doc) const {
  if (type != Type::kString) throw InputError(doc + ": expected a string");
  return text;
}

Value parse(const std::string& xml, const std::string& doc) { return Parser(xml, doc).document(); }

}  // namespace mpumesh::plist
