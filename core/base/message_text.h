// Outside text echoed in an error message, quoted and kept on one line.
//
// A message names the value it refuses ("unknown feature mode 'x'"), and that value comes from a
// file or a request: a newline or another control byte in it would split the message, and a
// reader of the log would take the rest for a second line of its own. Control bytes are shown
// escaped (\n, \t, \xNN); everything else is kept as it is.
#ifndef TINBASE_CORE_BASE_MESSAGE_TEXT_H_
#define TINBASE_CORE_BASE_MESSAGE_TEXT_H_

#include <cstdio>
#include <string>
#include <string_view>

namespace tinbase {

// `text` with its control bytes escaped.
inline std::string OneLineText(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

// `text` between single quotes, with its control bytes escaped.
inline std::string QuotedForMessage(std::string_view text) {
  std::string out(1, '\'');
  out.append(OneLineText(text));
  out.push_back('\'');
  return out;
}

}  // namespace tinbase

#endif  // TINBASE_CORE_BASE_MESSAGE_TEXT_H_
