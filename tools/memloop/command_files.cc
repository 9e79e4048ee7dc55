#include "command_files.h"

#include <filesystem>

#include "input/bag_sequence.h"
#include "input/dataset_listing.h"
#include "storage/sql_connection.h"

namespace memloop::cli {

std::vector<NamedPath> RunInputs(const std::string& input, const SequenceOptions& options) {
  std::error_code error;
  if (input.empty() || !std::filesystem::exists(input, error)) return {};
  if (!std::filesystem::is_directory(input, error)) return {{"the input", input}};
  if (IsBag(input)) return {{"the input bag folder", input, true}};
  const DatasetListing listing = ListDataset(input, options.format);
  if (listing.format == InputFormat::kFolder) return {{"the input folder", input, true}};
  std::vector<NamedPath> inputs = {{"the input's listing", listing.listing}};
  for (const ListedImage& image : listing.images) {
    inputs.push_back({"an image of the input", image.path});
  }
  return inputs;
}

std::vector<NamedPath> MapFiles(const std::string& path, const std::string& role) {
  if (path.empty() || IsServerMap(path)) return {};  // a server's map is no file
  std::vector<NamedPath> files = {{role, path}};
  for (const char* suffix : {"-wal", "-shm", "-lock"}) {
    files.push_back({role + "'s " + (suffix + 1) + " file", path + suffix});
  }
  return files;
}

std::vector<NamedPath> FileIfGiven(const std::string& path, const std::string& role) {
  if (path.empty()) return {};
  return {{role, path}};
}

}  // namespace memloop::cli
