#include "strict_yaml.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include "stridemap/io/text_file.hpp"

namespace stridemap::io_detail {

namespace {

// Sees only where documents start. yaml-cpp 0.7 can get stuck on some
// invalid text (a ',' outside a flow collection): its parser then reports
// the same empty document at the same place for ever, and YAML::LoadAll
// never returns (and YAML::Load returns a null node as if the file were
// empty). A document that starts where the previous one started is that.
class DocumentStarts : public YAML::EventHandler {
 public:
  YAML::Mark last_start;  // of the last document
  YAML::Mark content;     // of its first node (the line a user sees)
  void OnDocumentStart(const YAML::Mark& mark) override {
    last_start = content = mark;
    seen_content_ = false;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { node(mark); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { node(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string&) override { node(mark); }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark);
  }
  void OnMapEnd() override {}

 private:
  void node(const YAML::Mark& mark) {
    if (!seen_content_) content = mark;
    seen_content_ = true;
  }
  bool seen_content_ = false;
};

std::string describe_character_at(const std::string& text, int pos) {
  if (pos < 0 || static_cast<std::size_t>(pos) >= text.size()) return "the end of the text";
  const unsigned char c = static_cast<unsigned char>(text[static_cast<std::size_t>(pos)]);
  if (c >= 0x20 && c < 0x7f) return std::string("'") + static_cast<char>(c) + "'";
  char code[8];
  std::snprintf(code, sizeof code, "0x%02x", c);
  return std::string("byte ") + code;
}

}  // namespace

YAML::Node load_single_document(const std::string& text, const std::string& source_name) {
  const auto fail = [&](int line, const std::string& what) -> InputError {
    return InputError(source_name + ":" + std::to_string(std::max(1, line + 1)) + ": " + what);
  };
  try {
    std::istringstream input(text);
    YAML::Parser parser(input);
    DocumentStarts starts;
    int documents = 0;
    int second_line = 0;
    int previous_pos = -1;
    while (parser.HandleNextDocument(starts)) {
      if (starts.last_start.pos == previous_pos) {
        throw fail(starts.last_start.line, "not valid YAML: cannot read on from " +
                                               describe_character_at(text, starts.last_start.pos));
      }
      previous_pos = starts.last_start.pos;
      if (++documents == 2) second_line = starts.content.line;
    }
    if (documents > 1) {
      throw fail(second_line, "expected one YAML document, found " + std::to_string(documents));
    }
    return documents == 0 ? YAML::Node() : YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw fail(error.mark.line, "not valid YAML: " + error.msg);
  }
}

std::string read_text_file(const std::string& path, const std::string& what) {
  io::refuse_folder(path, what);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot read " + what + ": " + std::strerror(errno));
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) throw InputError(path + ": cannot read " + what + ": " + std::strerror(errno));
  return contents.str();
}

}  // namespace stridemap::io_detail
