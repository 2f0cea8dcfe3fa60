// Error types of the engine. Messages are meant for users: they name the file,
// the line (or byte offset) and what was expected.
#pragma once
#include <stdexcept>
#include <string>

namespace anisurf {

// Base of every error the engine throws on bad input or a refused operation.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file could not be read or written: names the file and the place.
class IoError : public Error {
 public:
  using Error::Error;
};

// A mesh was refused (non-manifold beyond repair, empty, invalid ids ...).
class TopologyError : public Error {
 public:
  using Error::Error;
};

}  // namespace anisurf
