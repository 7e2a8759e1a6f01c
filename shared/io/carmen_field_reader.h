#ifndef FLEETMAP_SHARED_IO_CARMEN_FIELD_READER_H_
#define FLEETMAP_SHARED_IO_CARMEN_FIELD_READER_H_

// Internal to carmen_parse.cc: bounds-checked, in-order reading of one line's tokens.

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "shared/core/rigid2d.h"
#include "shared/io/carmen_parse.h"

namespace fleetmap {
namespace carmen {

inline std::string Quote(std::string_view token) {
  constexpr size_t kMaxShown = 20;
  std::string shown(token.substr(0, kMaxShown));
  if (token.size() > kMaxShown) shown += "...";
  return "'" + shown + "'";
}

// Reads tokens in order, remembering the first failure so parsers stay linear. Every read is
// checked against the number of tokens left, so no input can make it read past the line.
class FieldReader {
 public:
  FieldReader(const Tokens& tokens, std::string_view type) : tokens_(tokens), type_(type) {}

  bool Double(const char* what, double* value) {
    if (!Have(1, what)) return false;
    if (!ParseDouble(tokens_[next_], value)) {
      return Fail(std::string(what) + " " + Quote(tokens_[next_]) + " is not a number");
    }
    ++next_;
    return true;
  }
  bool FiniteDouble(const char* what, double* value) {
    if (!Double(what, value)) return false;
    if (!std::isfinite(*value)) return Fail(std::string(what) + " is not finite");
    return true;
  }
  bool Pose(const char* what, Rigid2d* pose, double raw[3]) {
    for (int i = 0; i < 3; ++i) {
      if (!Double(what, &raw[i])) return false;
    }
    if (!std::isfinite(raw[0]) || !std::isfinite(raw[1]) || !std::isfinite(raw[2])) {
      return Fail(std::string(what) + " is not finite");
    }
    *pose = Rigid2d(raw[0], raw[1], raw[2]);
    return true;
  }
  bool Count(const char* what, int max_count, long* count) {
    if (!Have(1, what)) return false;
    if (!ParseInt(tokens_[next_], count)) {
      return Fail(std::string(what) + " " + Quote(tokens_[next_]) + " is not an integer");
    }
    if (*count < 0 || *count > max_count) {
      return Fail(std::string(what) + " " + std::to_string(*count) + " is outside [0, " +
                  std::to_string(max_count) + "]");
    }
    ++next_;
    return true;
  }
  bool Ranges(long count, std::vector<float>* ranges) {
    if (!Have(static_cast<size_t>(count), "ranges")) return false;
    ranges->resize(static_cast<size_t>(count));
    for (long i = 0; i < count; ++i) {
      double range;
      if (!ParseDouble(tokens_[next_], &range)) {
        return Fail("range " + std::to_string(i) + " " + Quote(tokens_[next_]) +
                    " is not a number");
      }
      // Non-finite readings become no-returns in MakeLaserScan.
      (*ranges)[static_cast<size_t>(i)] = static_cast<float>(range);
      ++next_;
    }
    return true;
  }
  bool Skip(long count, const char* what) {
    if (!Have(static_cast<size_t>(count), what)) return false;
    next_ += static_cast<size_t>(count);
    return true;
  }
  // Fails unless at least `count` more tokens exist (so no read can run past the line).
  bool Have(size_t count, const char* what) {
    if (!ok_) return false;
    if (left() < count) return Fail(std::string("line ends before ") + what);
    return true;
  }
  // Fails unless exactly `count` tokens are left.
  bool Expect(size_t count, const std::string& what) {
    if (!ok_) return false;
    const size_t left = tokens_.size() - next_;
    if (left != count) {
      return Fail("expected " + what + " (" + std::to_string(count) + " values), found " +
                  std::to_string(left));
    }
    return true;
  }
  size_t left() const { return tokens_.size() - next_; }
  bool Fail(const std::string& message) {
    if (ok_) error_ = std::string(type_) + ": " + message;
    ok_ = false;
    return false;
  }
  const std::string& error() const { return error_; }

 private:
  const Tokens& tokens_;
  std::string_view type_;
  size_t next_ = 1;
  bool ok_ = true;
  std::string error_;
};

}  // namespace carmen
}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_FIELD_READER_H_
