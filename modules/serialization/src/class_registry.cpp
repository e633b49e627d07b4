#include "rove/serialization/class_registry.h"

#include <algorithm>
#include <mutex>
#include <utility>

#include "rove/core/check.h"

namespace rove {

ClassRegistry& ClassRegistry::global() {
  static ClassRegistry registry;
  return registry;
}

void ClassRegistry::add(std::string name, Factory factory, bool replace) {
  ROVE_CHECK_MSG(!name.empty() && name.size() <= 255,
                 "class names are 1..255 bytes, got {} bytes", name.size());
  ROVE_CHECK_MSG(static_cast<bool>(factory), "null factory for class '{}'", name);
  std::unique_lock lock(mutex_);
  auto it = factories_.find(name);
  if (it != factories_.end()) {
    ROVE_CHECK_MSG(replace, "class '{}' is already registered", name);
    it->second = std::move(factory);
    return;
  }
  factories_.emplace(std::move(name), std::move(factory));
}

std::unique_ptr<Serializable> ClassRegistry::create(std::string_view name) const {
  Factory f;
  {
    std::shared_lock lock(mutex_);
    auto it = factories_.find(name);
    if (it == factories_.end()) return nullptr;
    f = it->second;
  }
  return f();
}

bool ClassRegistry::contains(std::string_view name) const {
  std::shared_lock lock(mutex_);
  return factories_.find(name) != factories_.end();
}

std::vector<std::string> ClassRegistry::names() const {
  std::vector<std::string> out;
  {
    std::shared_lock lock(mutex_);
    out.reserve(factories_.size());
    for (const auto& [name, f] : factories_) out.push_back(name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rove
