// Two kinds of failure, kept apart (docs/style.md, "Errors"):
//  - PUFF_CHECK: a broken internal promise. Prints file:line and the condition, then aborts.
//  - puff::Error / puff::Result<T>: bad input (a mesh, a scene, an image, a flag). Carries one
//    human-readable line, "FILE: problem", that `main` prints as "TOOL: error: FILE: problem".
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <variant>

#define PUFF_CHECK(cond)                                                                     \
  do {                                                                                       \
    if (!(cond)) {                                                                           \
      std::fprintf(stderr, "%s:%d: internal check failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                          \
    }                                                                                        \
  } while (0)

namespace puff {

/// One line saying what went wrong with which input, e.g. "art/puffs/x.obj: no faces".
struct Error {
  std::string message;

  /// "FILE: what". An empty file gives just "what".
  static Error at(const std::filesystem::path& file, const std::string& what) {
    return Error{file.empty() ? what : file.string() + ": " + what};
  }
};

/// Either a value or an Error. Test with `if (!r)`, read with `*r` / `r->` / `r.error()`.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}
  Result(Error error) : v_(std::move(error)) {}
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & {
    PUFF_CHECK(ok());
    return std::get<0>(v_);
  }
  const T& value() const& {
    PUFF_CHECK(ok());
    return std::get<0>(v_);
  }
  T&& value() && {
    PUFF_CHECK(ok());
    return std::get<0>(std::move(v_));
  }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T&& operator*() && { return std::move(*this).value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const Error& error() const {
    PUFF_CHECK(!ok());
    return std::get<1>(v_);
  }

 private:
  std::variant<T, Error> v_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)), failed_(true) {}
  bool ok() const { return !failed_; }
  explicit operator bool() const { return ok(); }
  const Error& error() const {
    PUFF_CHECK(failed_);
    return error_;
  }

 private:
  Error error_;
  bool failed_ = false;
};

}  // namespace puff

/// Evaluates a Result<void> expression and returns its error from the enclosing function.
#define PUFF_TRY(expr)                                  \
  do {                                                  \
    auto puffTryResult_ = (expr);                       \
    if (!puffTryResult_) return puffTryResult_.error(); \
  } while (0)

/// Evaluates a Result<T> expression: returns its error from the enclosing function, else moves its
/// value into `lhs`, a declaration or an lvalue:
///   PUFF_TRY_ASSIGN(auto atlas, core::loadAtlas(path));
///   PUFF_TRY_ASSIGN(m.program, core::buildProgram({"media/fullscreen.vert", "media/blur.frag"}));
/// One statement at block scope (it declares a hidden local named after the line).
#define PUFF_TRY_ASSIGN(lhs, expr) PUFF_TRY_ASSIGN_(PUFF_CONCAT_(puffTryAssign_, __LINE__), lhs, expr)
#define PUFF_TRY_ASSIGN_(tmp, lhs, expr) \
  auto tmp = (expr);                     \
  if (!tmp) return tmp.error();          \
  lhs = std::move(*tmp)
#define PUFF_CONCAT_(a, b) PUFF_CONCAT_INNER_(a, b)
#define PUFF_CONCAT_INNER_(a, b) a##b
