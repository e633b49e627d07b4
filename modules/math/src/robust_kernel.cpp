#include "rove/math/robust_kernel.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove {

std::string_view to_string(RobustKernelType type) {
  switch (type) {
    case RobustKernelType::Trivial: return "none";
    case RobustKernelType::Huber: return "huber";
    case RobustKernelType::Cauchy: return "cauchy";
    case RobustKernelType::Tukey: return "tukey";
    case RobustKernelType::GemanMcClure: return "geman_mcclure";
    case RobustKernelType::Dcs: return "dcs";
  }
  ROVE_CHECK_MSG(false, "invalid RobustKernelType value {}", static_cast<int>(type));
  return {};
}

double default_kernel_parameter(RobustKernelType type) {
  switch (type) {
    case RobustKernelType::Trivial: return 0.0;
    case RobustKernelType::Huber: return HuberKernel{}.delta;
    case RobustKernelType::Cauchy: return CauchyKernel{}.c;
    case RobustKernelType::Tukey: return TukeyKernel{}.c;
    case RobustKernelType::GemanMcClure: return GemanMcClureKernel{}.c;
    case RobustKernelType::Dcs: return DcsKernel{}.phi;
  }
  ROVE_CHECK_MSG(false, "invalid RobustKernelType value {}", static_cast<int>(type));
  return 0.0;
}

RobustKernel::RobustKernel(RobustKernelType type)
    : RobustKernel(type, default_kernel_parameter(type)) {}

RobustKernel::RobustKernel(RobustKernelType type, double parameter) : type_(type) {
  // to_string validates the enum value.
  const std::string_view name = rove::to_string(type);
  if (type == RobustKernelType::Trivial) {
    parameter_ = 0.0;
    return;
  }
  ROVE_CHECK_MSG(std::isfinite(parameter) && parameter > 0.0,
                 "robust kernel '{}' needs a finite parameter > 0, got {}", name, parameter);
  parameter_ = parameter;
}

std::string RobustKernel::to_string() const {
  if (type_ == RobustKernelType::Trivial) return "none";
  // {} prints the shortest text that reads back to the same double.
  return fmt::format("{}:{}", rove::to_string(type_), parameter_);
}

namespace {

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

[[noreturn]] void fail(std::string_view source, std::string problem) {
  throw ParseError({std::string(source), std::nullopt, std::nullopt, "robust kernel"},
                   std::move(problem));
}

}  // namespace

RobustKernel parse_robust_kernel(std::string_view text, std::string_view source) {
  const std::string_view whole = trim(text);
  const auto colon = whole.find(':');
  const std::string name = lower(trim(whole.substr(0, colon)));
  if (name.empty()) fail(source, fmt::format("empty kernel name in '{}'", text));

  static constexpr std::array<std::pair<std::string_view, RobustKernelType>, 9> kNames{{
      {"none", RobustKernelType::Trivial},
      {"trivial", RobustKernelType::Trivial},
      {"l2", RobustKernelType::Trivial},
      {"huber", RobustKernelType::Huber},
      {"cauchy", RobustKernelType::Cauchy},
      {"tukey", RobustKernelType::Tukey},
      {"geman_mcclure", RobustKernelType::GemanMcClure},
      {"gm", RobustKernelType::GemanMcClure},
      {"dcs", RobustKernelType::Dcs},
  }};
  const auto* it = kNames.begin();
  while (it != kNames.end() && it->first != name) ++it;
  if (it == kNames.end()) {
    fail(source, fmt::format("unknown kernel '{}' (expected none, huber, cauchy, tukey, "
                             "geman_mcclure or dcs)",
                             name));
  }
  const RobustKernelType type = it->second;
  if (colon == std::string_view::npos) return RobustKernel(type);

  const std::string_view param_text = trim(whole.substr(colon + 1));
  if (type == RobustKernelType::Trivial) {
    fail(source, fmt::format("kernel '{}' takes no parameter, got '{}'", name, param_text));
  }
  if (param_text.empty()) fail(source, fmt::format("missing parameter after '{}:'", name));
  double value = 0.0;
  const char* first = param_text.data();
  const char* last = first + param_text.size();
  const auto [end, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || end != last) {
    fail(source, fmt::format("parameter '{}' of kernel '{}' is not a number", param_text, name));
  }
  if (!std::isfinite(value) || value <= 0.0) {
    fail(source,
         fmt::format("parameter of kernel '{}' must be finite and > 0, got {}", name, param_text));
  }
  return RobustKernel(type, value);
}

}  // namespace rove
