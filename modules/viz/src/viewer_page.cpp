#include "rove/viz/viewer_page.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <filesystem>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {

namespace detail {
extern const std::string_view kViewerPageTemplate;
extern const std::string_view kViewerScript;
}  // namespace detail

namespace {

constexpr std::array<std::string_view, 3> kThreeScripts = {
    "three.min.js", "examples/js/loaders/GLTFLoader.js", "examples/js/controls/OrbitControls.js"};

std::string with_scripts(std::string_view scripts) {
  std::string page(detail::kViewerPageTemplate);
  const std::string_view marker = "@ROVE_SCRIPTS@";
  const std::size_t at = page.find(marker);
  ROVE_CHECK_MSG(at != std::string::npos, "the page template lacks {}", marker);
  page.replace(at, marker.size(), scripts);
  return page;
}

std::string start_call(const ViewerPageOptions& o, std::string_view source) {
  ROVE_CHECK_GT(o.lod_budget, std::size_t{0});
  std::string pick = "null";
  if (o.pick_at) {
    ROVE_CHECK_MSG(std::isfinite((*o.pick_at)[0]) && std::isfinite((*o.pick_at)[1]), "pick_at must be finite");
    pick = fmt::format("[{}, {}]", (*o.pick_at)[0], (*o.pick_at)[1]);
  }
  return fmt::format("<script>roveView({{{}, lodBudget: {}, bench: {}, panel: {}, pickAt: {}}});</script>\n", source,
                     o.lod_budget, o.bench ? "true" : "false", o.panel ? "true" : "false", pick);
}

// A script inlined into a page must not close its <script> element early.
std::string inline_script(std::string_view code) {
  std::string out = "<script>\n";
  std::size_t from = 0;
  while (true) {
    const std::size_t at = code.find("</script", from);
    out.append(code.substr(from, at == std::string_view::npos ? std::string_view::npos : at - from));
    if (at == std::string_view::npos) break;
    out += "<\\/script";
    from = at + 8;
  }
  out += "\n</script>\n";
  return out;
}

}  // namespace

std::span<const std::string_view> three_script_files() noexcept { return kThreeScripts; }

std::string_view viewer_script() noexcept { return detail::kViewerScript; }

std::string read_three_script(const std::string& three_dir, std::string_view relative) {
  const std::filesystem::path path = std::filesystem::path(three_dir) / relative;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw IoError(path.string(),
                  "three.js is missing: install Debian's libjs-three (scripts/install-deps does) or point "
                  "--three-dir at a folder holding three.min.js and examples/js/");
  }
  return read_input_file(path, std::uint64_t{64} << 20, "three.js script");
}

std::string served_page(const ViewerPageOptions& options) {
  std::string scripts;
  for (std::string_view f : kThreeScripts) scripts += fmt::format("<script src=\"three/{}\"></script>\n", f);
  scripts += "<script src=\"viewer.js\"></script>\n";
  scripts += start_call(options, "url: 'scene.glb'");
  return with_scripts(scripts);
}

std::string standalone_page(std::span<const std::uint8_t> glb, const ViewerPageOptions& options) {
  std::string scripts;
  for (std::string_view f : kThreeScripts) scripts += inline_script(read_three_script(options.three_dir, f));
  scripts += inline_script(detail::kViewerScript);
  scripts += "<script id=\"rove-glb\" type=\"application/octet-stream\">";
  scripts += base64_encode(glb);
  scripts += "</script>\n";
  scripts += start_call(options, "base64: document.getElementById('rove-glb').textContent");
  return with_scripts(scripts);
}

std::string page_stats_json(std::string_view dom) {
  const std::string_view open = "<pre id=\"rove-stats\">";
  const std::size_t at = dom.find(open);
  if (at == std::string_view::npos) return "";
  const std::size_t end = dom.find("</pre>", at);
  if (end == std::string_view::npos) return "";
  const std::string_view body = dom.substr(at + open.size(), end - at - open.size());
  std::string out;
  static constexpr std::pair<std::string_view, char> kEntities[] = {
      {"&quot;", '"'}, {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&#39;", '\''}};
  for (std::size_t i = 0; i < body.size();) {
    bool replaced = false;
    for (const auto& [entity, c] : kEntities) {
      if (body.substr(i, entity.size()) == entity) {
        out += c;
        i += entity.size();
        replaced = true;
        break;
      }
    }
    if (!replaced) out += body[i++];
  }
  return out;
}

std::string base64_encode(std::span<const std::uint8_t> bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    for (int s = 18; s >= 0; s -= 6) out += kDigits[(v >> s) & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t v = std::uint32_t{bytes[i]} << 16;
    if (rest == 2) v |= std::uint32_t{bytes[i + 1]} << 8;
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += rest == 2 ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace rove
