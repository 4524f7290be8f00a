#pragma once
// The one error type of clothsim: thrown at the input boundary (io/, model building), caught once in
// tools/ and turned into exit code 2. Kernels never throw.
#include <stdexcept>
#include <string>

namespace clothsim {

class Error : public std::runtime_error {
 public:
  Error(std::string file, int line, std::string message)
      : std::runtime_error(format(file, line, message)),
        file_(std::move(file)), line_(line), message_(std::move(message)) {}
  Error(std::string file, std::string message) : Error(std::move(file), 0, std::move(message)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 0 when unknown
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& message) {
    std::string s;
    s.reserve(file.size() + message.size() + 16);
    s.append(file);
    if (line > 0) s.append(":").append(std::to_string(line));
    if (!s.empty()) s.append(": ");
    s.append(message);
    return s;
  }
  std::string file_;
  int line_;
  std::string message_;
};

}  // namespace clothsim
