#include "strict_yaml.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace stridemap::io_detail {

YAML::Node load_single_document(const std::string& text, const std::string& source_name) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(text);
  } catch (const YAML::Exception& error) {
    throw InputError(source_name + ":" + std::to_string(std::max(1, error.mark.line + 1)) + ": not valid YAML: " + error.msg);
  }
  if (documents.size() > 1) {
    throw InputError(source_name + ":" + std::to_string(std::max(1, documents[1].Mark().line + 1)) +
                     ": expected one YAML document, found " + std::to_string(documents.size()));
  }
  return documents.empty() ? YAML::Node() : documents.front();
}

std::string read_text_file(const std::string& path, const std::string& what) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot read " + what + ": " + std::strerror(errno));
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) throw InputError(path + ": cannot read " + what + ": " + std::strerror(errno));
  return contents.str();
}

}  // namespace stridemap::io_detail
