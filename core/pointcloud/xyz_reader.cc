#include "core/pointcloud/xyz_reader.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <string_view>
#include <vector>

#include "core/base/number_text.h"

namespace tinbase {
namespace {

// Millions of lines are read a chunk at a time and split in place: a line costs no allocation,
// and the messages that name a line are only built when it is wrong.
constexpr size_t kChunkBytes = size_t{8} << 20;

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsBlank(s.back())) s.remove_suffix(1);
  return s;
}

// The first three fields of a line and how many it has (counted exactly while fewer than three:
// only then does a message give the count).
struct Fields {
  std::string_view field[3];
  size_t count = 0;
  void Add(std::string_view f) {
    if (count < 3) field[count] = f;
    ++count;
  }
};

// A line with a comma is CSV (fields trimmed, so "1, 2,3" works and "1,,3" has an empty
// field; an empty last field is no field); any other line is split at runs of whitespace.
// REQUIRES: `line` does not start with a blank.
Fields SplitFields(std::string_view line) {
  Fields out;
  if (line.find(',') != std::string_view::npos) {
    size_t begin = 0;
    while (out.count < 3) {
      const size_t comma = line.find(',', begin);
      if (comma == std::string_view::npos) {
        const std::string_view last = Trim(line.substr(begin));
        if (!last.empty()) out.Add(last);
        break;
      }
      out.Add(Trim(line.substr(begin, comma - begin)));
      begin = comma + 1;
    }
    return out;
  }
  size_t i = 0;
  while (out.count < 3) {
    while (i < line.size() && IsBlank(line[i])) ++i;
    if (i == line.size()) break;
    const size_t begin = i;
    while (i < line.size() && !IsBlank(line[i])) ++i;
    out.Add(line.substr(begin, i - begin));
  }
  return out;
}

// Appends the points of successive lines to a cloud; knows whether a header may still come.
class LineParser {
 public:
  LineParser(const std::string& name, PointCloud& cloud) : name_(name), cloud_(cloud) {}

  Status Parse(std::string_view line, int64_t line_no) {
    size_t start = 0;
    while (start < line.size() && IsBlank(line[start])) ++start;
    if (start == line.size() || line[start] == '#') return Status::Ok();
    const Fields fields = SplitFields(line.substr(start));
    if (fields.count < 3) {
      return Status::InvalidArgument(Where(line_no) + ": expected x y z, found " +
                                     std::to_string(fields.count) + " field(s)");
    }
    NumberText v[3];
    for (int i = 0; i < 3; ++i) v[i] = ParseNumberText(fields.field[i]);
    const auto not_number = [](const NumberText& n) {
      return n.problem == NumberProblem::kNotANumber;
    };
    if (!seen_data_ && not_number(v[0]) && not_number(v[1]) && not_number(v[2])) {
      seen_data_ = true;  // a header line of names
      return Status::Ok();
    }
    seen_data_ = true;
    static const char* kAxis[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      if (v[i].problem) {
        return Status::InvalidArgument(Where(line_no) + ": " + kAxis[i] + " '" +
                                       std::string(fields.field[i]) + "' " +
                                       DescribeNumberProblem(*v[i].problem));
      }
    }
    CloudPoint p;
    p.x = v[0].value;
    p.y = v[1].value;
    p.z = v[2].value;
    cloud_.points.push_back(p);
    return Status::Ok();
  }

 private:
  std::string Where(int64_t line_no) const { return name_ + ", line " + std::to_string(line_no); }

  const std::string& name_;
  PointCloud& cloud_;
  bool seen_data_ = false;
};

}  // namespace

Result<PointCloud> ReadXyz(std::istream& in, const std::string& name) {
  PointCloud cloud;
  LineParser parser(name, cloud);
  std::vector<char> buffer;
  size_t filled = 0;  // bytes of buffer holding a line not yet complete
  int64_t line_no = 0;
  for (;;) {
    // A line longer than a chunk grows the buffer rather than being cut.
    if (buffer.size() < filled + kChunkBytes) buffer.resize(filled + kChunkBytes);
    in.read(buffer.data() + filled, static_cast<std::streamsize>(kChunkBytes));
    if (in.bad()) return Status::IOError(name + ": read error");
    const size_t got = static_cast<size_t>(in.gcount());
    filled += got;
    const char* data = buffer.data();
    size_t pos = 0;
    while (const void* nl = std::memchr(data + pos, '\n', filled - pos)) {
      const size_t end = static_cast<size_t>(static_cast<const char*>(nl) - data);
      TB_RETURN_IF_ERROR(parser.Parse(std::string_view(data + pos, end - pos), ++line_no));
      pos = end + 1;
    }
    if (got < kChunkBytes) {  // end of input: a last line without '\n' still counts
      if (pos < filled) {
        TB_RETURN_IF_ERROR(parser.Parse(std::string_view(data + pos, filled - pos), ++line_no));
      }
      return cloud;
    }
    std::memmove(buffer.data(), data + pos, filled - pos);
    filled -= pos;
  }
}

Result<PointCloud> ReadXyz(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::IOError(path + ": cannot open file");
  return ReadXyz(in, path);
}

}  // namespace tinbase
