#pragma once
/// \file
/// Where a file named in an MRPT application config is: MRPT's applications
/// open it from the working folder, MRPT's own config files expect it
/// beside (relative to) themselves.

#include <string>

namespace rove {

/// `path` as it exists: as written if that exists, else relative to the
/// folder of `config_file`. Empty `path` gives empty. Throws ConfigError
/// naming `config_file`, [`section`] and `key` when neither exists.
std::string resolve_config_path(const std::string& config_file, const std::string& section,
                                const std::string& key, const std::string& path);

}  // namespace rove
