#pragma once
// The one exception type thrown by Porter loaders (URDF, meshes, YAML configs, scenes).
// Bad input at load time throws; nothing else in the core libraries throws.

#include <stdexcept>
#include <string>

namespace porter {

/// A file could not be turned into a model. The message always names the file, the element or
/// key inside it (when there is one) and what is wrong, so a user can fix the file:
///   "config/payloads/t_bar.yaml: key 'grasp.xyz': expected a sequence of 3 numbers"
class LoadError : public std::runtime_error {
 public:
  LoadError(std::string file, std::string element, std::string reason)
      : std::runtime_error(compose(file, element, reason)),
        file_(std::move(file)), element_(std::move(element)), reason_(std::move(reason)) {}

  const std::string& file() const { return file_; }
  const std::string& element() const { return element_; }
  const std::string& reason() const { return reason_; }

 private:
  static std::string compose(const std::string& f, const std::string& e, const std::string& r) {
    std::string s = f.empty() ? std::string("<input>") : f;
    if (!e.empty()) s += ": " + e;
    return s + ": " + r;
  }
  std::string file_, element_, reason_;
};

}  // namespace porter
