// The comma-separated lists of HTTP request headers (Accept, Accept-Encoding; RFC 9110,
// section 12.5): each element a value with ";name=value" parameters, the weight "q" read as a
// number. Parsing never fails: a malformed element is kept as the client wrote it, with q = 1, so
// negotiation decides as if the client had not asked for it specially. Thread-safety: pure.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace tinbase::service {

struct HeaderElement {
  std::string value;                          // lower case, "application/vnd.quantized-mesh"
  std::map<std::string, std::string> params;  // names lower case, values unquoted, without q
  double q = 1;                               // 0 to 1
};

// The elements of `header` in the order given; commas inside quoted parameter values do not split.
std::vector<HeaderElement> ParseHeaderList(const std::string& header);

}  // namespace tinbase::service
