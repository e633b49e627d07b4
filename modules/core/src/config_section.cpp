#include "rove/core/config_section.h"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove {

namespace {
bool starts_with_icase(std::string_view text, std::string_view prefix) {
  if (text.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(text[i])) !=
        std::tolower(static_cast<unsigned char>(prefix[i]))) {
      return false;
    }
  }
  return true;
}
}  // namespace

ConfigSection::ConfigSection(const IniFile& ini, std::string section,
                             std::vector<IgnoredConfigKey>* ignored)
    : ini_(&ini), section_(std::move(section)), ignored_(ignored) {}

double ConfigSection::get_in_range(std::string_view key, double fallback, double lo,
                                   double hi) const {
  const double v = get<double>(key, fallback);
  if (!(v >= lo && v <= hi)) {
    fail(key, fmt::format("{} is outside the accepted range [{}, {}]", v, lo, hi));
  }
  return v;
}

void ConfigSection::ignore(std::initializer_list<std::string_view> keys,
                           std::string_view reason) const {
  for (std::string_view k : keys) {
    if (!ini_->has(section_, k)) continue;
    (void)ini_->raw(section_, k);  // counts as read
    if (ignored_ != nullptr) {
      // Report the key with the spelling of the file.
      std::string spelled(k);
      for (const auto& name : ini_->keys(section_)) {
        if (name.size() == k.size() && starts_with_icase(name, k)) spelled = name;
      }
      ignored_->push_back({section_, spelled, std::string(reason)});
    }
  }
}

void ConfigSection::ignore_prefix(std::string_view prefix, std::string_view reason) const {
  for (const auto& k : ini_->keys(section_)) {
    if (!starts_with_icase(k, prefix)) continue;
    (void)ini_->raw(section_, k);
    if (ignored_ != nullptr) ignored_->push_back({section_, k, std::string(reason)});
  }
}

void ConfigSection::check_all_read() const {
  const auto unread = ini_->unread_keys(section_);
  if (unread.empty()) return;
  std::string all;
  for (const auto& k : unread) all += (all.empty() ? "" : ", ") + k;
  const auto line = ini_->line(section_, unread.front());
  fail(unread.front(),
       fmt::format("unknown key (line {}); every unknown key of this section: {}",
                   line ? *line : 0, all));
}

void ConfigSection::fail(std::string_view key, const std::string& problem) const {
  throw ConfigError(ini_->source(), section_, std::string(key), problem);
}

}  // namespace rove
