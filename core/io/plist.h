// A minimal Apple XML property-list parser: dict, array, key, string, integer, real,
// true, false. Enough for InVesalius project files; rejects anything malformed with
// InputError naming the document.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace mpumesh::plist {

struct Value {
  enum class Type { kDict, kArray, kString, kInteger, kReal, kBool } type = Type::kString;
  std::string text;  // string, or the number's literal
  double number = 0;
  std::map<std::string, Value> dict;
  std::vector<Value> array;

  // Lookups that throw InputError mentioning `doc` when the key or type is wrong.
  const Value& at(const std::string& key, const std::string& doc) const;
  double as_number(const std::string& doc) const;
  const std::string& as_string(const std::string& doc) const;
};

Value parse(const std::string& xml, const std::string& doc);

}  // namespace mpumesh::plist
