#pragma once
// SettingsView over a checked config section (core/settings_view.hpp): how a module's registry
// parsers read the config without JSON crossing into the module.
#include "config.hpp"

#include "millnet/core/settings_view.hpp"

#include <memory>
#include <string>
#include <string_view>

namespace millnet::app {

class JsonSettings final : public SettingsView {
public:
  /// `section` must outlive the view; `pointer` is its JSON pointer ("/pocket").
  JsonSettings(const Json& section, std::string pointer) : json_(&section), pointer_(std::move(pointer)) {}
  [[nodiscard]] double number(std::string_view key) const override;
  [[nodiscard]] std::int64_t integer(std::string_view key) const override;
  [[nodiscard]] bool flag(std::string_view key) const override;
  [[nodiscard]] std::string text(std::string_view key) const override;
  [[nodiscard]] bool is_text(std::string_view key) const override;
  [[nodiscard]] std::unique_ptr<SettingsView> section(std::string_view key) const override;
  [[nodiscard]] std::string pointer() const override { return pointer_; }

private:
  const Json& at(std::string_view key, bool (Json::*is)() const noexcept, const char* expected) const;
  const Json* json_;
  std::string pointer_;
};

}  // namespace millnet::app
