#pragma once
// A read-only view of one checked config section, for a module's own setting parsers (the parsers
// of an extension point's registry entries, e.g. pocket's planners). JSON stops in app/
// (ARCHITECTURE.md): app implements this view over its config, which was checked against the schema
// and had its defaults filled, so a key a parser asks for is there with the schema's type. Asking
// for a key that is not there, or with another type, throws millnet::Error naming its JSON pointer.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace millnet {

class SettingsView {
public:
  virtual ~SettingsView() = default;
  [[nodiscard]] virtual double number(std::string_view key) const = 0;
  [[nodiscard]] virtual std::int64_t integer(std::string_view key) const = 0;
  [[nodiscard]] virtual bool flag(std::string_view key) const = 0;
  [[nodiscard]] virtual std::string text(std::string_view key) const = 0;
  /// True when the key holds a string (a setting that may be a number or a word: "auto").
  [[nodiscard]] virtual bool is_text(std::string_view key) const = 0;
  /// The object at `key` (a sub-section).
  [[nodiscard]] virtual std::unique_ptr<SettingsView> section(std::string_view key) const = 0;
  /// The section's JSON pointer, for messages ("/pocket/zigzag").
  [[nodiscard]] virtual std::string pointer() const = 0;
};

}  // namespace millnet
