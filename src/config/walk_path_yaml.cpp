#include "stridemap/config/walk_path_yaml.hpp"

#include "strict_yaml.hpp"
#include "walk_path_reader.hpp"

namespace stridemap {

WalkPath parse_walk_path_yaml(const std::string& text, const std::string& source_name, const HeightField* terrain) {
  using namespace io_detail;
  StrictYamlReader reader(source_name);
  const YAML::Node root = load_single_document(text, source_name);
  if (!root.IsMap()) reader.fail(root, "", "expected a map with a walk_path section, got " + describe(root));
  const auto fields = reader.read_map(root, "", {"walk_path"});
  const Field* section = reader.find(fields, "walk_path");
  if (!section) reader.fail(root, "walk_path", "required section is missing");
  const WalkPath path = read_walk_path(reader, section->value, "walk_path");
  auto problem = walk_path_problem(path);
  if (!problem && terrain) problem = walk_path_extent_problem(path, *terrain);
  if (problem) reader.fail_at(problem->field_path, problem->message);
  return path;
}

WalkPath load_walk_path_yaml(const std::string& path, const HeightField* terrain) {
  return parse_walk_path_yaml(io_detail::read_text_file(path, "walk path file"), path, terrain);
}

}  // namespace stridemap
