// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <stdexcept>
#include <string>

namespace mirage {

// Setup and configuration errors. Messages start with the component and the input,
// e.g. "scene 'town.yaml': objects[3].material: unknown material 'glas'".
// Hot paths (per pulse, per packet) never throw; they return a status and count it.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};
// Bad content in a user-supplied file or option (YAML key, OBJ line, CSV row, CLI value).
class ConfigError : public Error {
  public:
    using Error::Error;
};
// A file or device that cannot be opened, read or written.
class IoError : public Error {
  public:
    using Error::Error;
};

}  // namespace mirage
