#pragma once
/// \file
/// Where the rove command line finds its bundled data (data/ of the source
/// tree, or share/rove/data of an installation).

#include <filesystem>

namespace rove::cli {

/// The bundled data folder: $ROVE_DATA_DIR if set; else share/rove/data next
/// to an installed binary; else the source tree's data/ the binary was built
/// from. Throws rove::IoError naming the places tried if none exists.
std::filesystem::path data_dir();

}  // namespace rove::cli
