// Parsing comma-separated header lists.
#include "service/header_lists.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace tinbase::service {

namespace {

std::string Trim(const std::string& text) {
  size_t begin = 0, end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Splits at `separator` outside double quotes.
std::vector<std::string> SplitOutsideQuotes(const std::string& text, char separator) {
  std::vector<std::string> parts(1);
  bool quoted = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted && c == '\\' && i + 1 < text.size()) {
      parts.back() += text[++i];
      continue;
    }
    if (c == '"') quoted = !quoted;
    if (c == separator && !quoted) {
      parts.emplace_back();
    } else {
      parts.back() += c;
    }
  }
  return parts;
}

std::string Unquote(const std::string& text) {
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"')
    return text.substr(1, text.size() - 2);
  return text;
}

// A q-value is 0 to 1 with at most three decimals; anything else counts as 1.
double ParseQ(const std::string& text) {
  char* end = nullptr;
  const double q = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(q >= 0 && q <= 1)) return 1;
  return q;
}

}  // namespace

std::vector<HeaderElement> ParseHeaderList(const std::string& header) {
  std::vector<HeaderElement> list;
  for (const std::string& raw : SplitOutsideQuotes(header, ',')) {
    const std::vector<std::string> parts = SplitOutsideQuotes(raw, ';');
    HeaderElement element;
    element.value = Lower(Trim(parts[0]));
    if (element.value.empty()) continue;
    for (size_t i = 1; i < parts.size(); ++i) {
      const std::string param = Trim(parts[i]);
      const size_t eq = param.find('=');
      const std::string name = Lower(Trim(param.substr(0, eq)));
      const std::string value = eq == std::string::npos ? "" : Unquote(Trim(param.substr(eq + 1)));
      if (name == "q") {
        element.q = ParseQ(value);
      } else if (!name.empty()) {
        element.params[name] = value;
      }
    }
    list.push_back(std::move(element));
  }
  return list;
}

}  // namespace tinbase::service
