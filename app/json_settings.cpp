#include "json_settings.hpp"

#include "millnet/core/error.hpp"

namespace millnet::app {

const Json& JsonSettings::at(std::string_view key, bool (Json::*is)() const noexcept, const char* expected) const {
  const std::string k(key);
  const auto it = json_->find(k);
  if (it == json_->end()) throw Error(pointer_ + "/" + k + ": missing (expected " + expected + ")");
  if (!((*it).*is)()) throw Error(pointer_ + "/" + k + ": expected " + expected + ", got " + it->type_name());
  return *it;
}

double JsonSettings::number(std::string_view key) const { return at(key, &Json::is_number, "a number").get<double>(); }

std::int64_t JsonSettings::integer(std::string_view key) const {
  return at(key, &Json::is_number, "an integer").get<std::int64_t>();
}

bool JsonSettings::flag(std::string_view key) const { return at(key, &Json::is_boolean, "true or false").get<bool>(); }

std::string JsonSettings::text(std::string_view key) const {
  return at(key, &Json::is_string, "a string").get<std::string>();
}

bool JsonSettings::is_text(std::string_view key) const {
  const auto it = json_->find(std::string(key));
  return it != json_->end() && it->is_string();
}

std::unique_ptr<SettingsView> JsonSettings::section(std::string_view key) const {
  return std::make_unique<JsonSettings>(at(key, &Json::is_object, "an object"), pointer_ + "/" + std::string(key));
}

}  // namespace millnet::app
