#pragma once
// The nodes' private parameters read against the list each node declares:
// a value of the wrong type or outside its range stops the node naming the
// parameter, a parameter the node does not know is named, and the same list
// is what `--help` prints and the start-up line logs (docs/ros.md). roscpp's
// own `param()` falls back to the default on a wrong type without a word,
// which is why the nodes do not use it. C++17 (see message_mapper.hpp).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>

namespace ros {
class NodeHandle;
}

namespace stridemap::ros_adapter {

/// Where the values come from: the parameter server, or a table (tests, --help).
class ParameterSource {
 public:
  virtual ~ParameterSource() = default;
  /// The value of `~name`, if it is set.
  virtual std::optional<XmlRpc::XmlRpcValue> get(const std::string& name) const = 0;
  /// Every name set under the private namespace, relative to it (`a/b` when nested).
  virtual std::vector<std::string> names() const = 0;
};

/// The parameter server, under the node handle's namespace (the node's `~`).
class ServerParameters final : public ParameterSource {
 public:
  explicit ServerParameters(const ros::NodeHandle& private_handle);
  std::optional<XmlRpc::XmlRpcValue> get(const std::string& name) const override;
  std::vector<std::string> names() const override;

 private:
  const ros::NodeHandle& handle_;
};

class TableParameters final : public ParameterSource {
 public:
  TableParameters() = default;
  explicit TableParameters(std::map<std::string, XmlRpc::XmlRpcValue> values) : values_(std::move(values)) {}
  std::optional<XmlRpc::XmlRpcValue> get(const std::string& name) const override;
  std::vector<std::string> names() const override;

 private:
  std::map<std::string, XmlRpc::XmlRpcValue> values_;
};

struct DeclaredParameter {
  std::string name;
  std::string type;           ///< "string", "path", "double", "int"
  std::string default_text;   ///< as --help shows it
  std::string help;
  std::string value_text;     ///< what was read (or the default), for the start-up line
};

class ParameterReader {
 public:
  explicit ParameterReader(const ParameterSource& source) : source_(source) {}

  std::string text(const std::string& name, const std::string& fallback, const std::string& help);
  /// A file the node reads or writes: a relative one is under `base` (the
  /// node's ROS_HOME), so it does not depend on the folder rosrun was
  /// started in. Empty stays empty.
  std::string path(const std::string& name, const std::string& fallback, const std::string& base,
                   const std::string& help);
  /// An int is taken as a double; NaN and infinities are refused.
  double number(const std::string& name, double fallback, double min, double max, const std::string& help);
  int integer(const std::string& name, int fallback, int min, int max, const std::string& help);

  /// Throws InputError naming every parameter set under `~` that no call above read.
  void refuse_unknown() const;
  const std::vector<DeclaredParameter>& declared() const { return declared_; }
  /// `name=value` for each parameter, for the start-up line.
  std::string summary() const;
  /// One line per parameter: `_name:=` type, default and what it is.
  std::string help_text() const;

 private:
  std::optional<XmlRpc::XmlRpcValue> lookup(const std::string& name) const;
  const ParameterSource& source_;
  std::vector<DeclaredParameter> declared_;
};

/// A node's `--help`: what it does, then every parameter `read_settings`
/// (a function of a ParameterReader&) declares, with its default.
template <typename ReadSettings>
std::string node_help(const std::string& program, const std::string& what, ReadSettings&& read_settings) {
  const TableParameters none;
  ParameterReader read(none);
  (void)read_settings(read);
  return program + ": " + what + "\nusage: rosrun stridemap " + program + " [_parameter:=value ...]\nparameters:\n" +
         read.help_text();
}

/// $ROS_HOME, else $HOME/.ros: where ROS puts a node's relative files.
std::string ros_home();

/// Whether the command line asks for help (`-h` or `--help`), which must be
/// answered before ros::init waits for a master.
bool asks_for_help(int argc, const char* const* argv);

}  // namespace stridemap::ros_adapter
