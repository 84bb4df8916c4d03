// io/: the whitespace-separated tokens of a text mesh file (gmsh ASCII, TetGen) with the line
// each is on, for error messages; optionally with '#' comments to the end of a line.
#pragma once

#include <string>
#include <string_view>

namespace tear {

class TextTokens {
 public:
  // `text` must outlive the reader.
  explicit TextTokens(const std::string& text, bool hash_comments = false)
      : text_(text), comments_(hash_comments) {}
  TextTokens(std::string&& text, bool hash_comments = false) = delete;

  // The next token, empty at the end of the text; line() is then its line.
  std::string_view next() {
    skip_space();
    const size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && !(comments_ && text_[pos_] == '#'))
      ++pos_;
    return std::string_view(text_.data() + start, pos_ - start);
  }
  // Whether only whitespace (and comments) is left.
  bool at_end() {
    skip_space();
    return pos_ == text_.size();
  }
  // The 1-based line of the last token (or of where the reader stopped).
  size_t line() const { return line_; }
  size_t pos() const { return pos_; }
  size_t remaining() const { return text_.size() - pos_; }
  // Moves to `pos` (at or after the current position), counting the lines passed.
  void skip_to(size_t pos) {
    for (; pos_ < pos && pos_ < text_.size(); ++pos_) line_ += text_[pos_] == '\n';
  }
  // Skips the rest of the current line, its newline included (where binary data begins).
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    if (pos_ < text_.size()) ++pos_, ++line_;
  }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  }
  void skip_space() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_, ++pos_;
      } else if (is_space(c)) {
        ++pos_;
      } else if (comments_ && c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  const std::string& text_;
  bool comments_;
  size_t pos_ = 0, line_ = 1;
};

}  // namespace tear
