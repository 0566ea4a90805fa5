// The one strict reading of numbers, sizes and lists that every layer uses: command-line
// values, spec options ("tile=32"), trace files and link specs. Strict means the whole text
// is the value: no leading blanks, no trailing characters, nothing non-finite ("2x", " 2",
// "nan", "inf" and "" are all refused). Standard library only.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace multiray {

// A finite number filling the whole of `text`; nullopt otherwise.
std::optional<double> parse_number(std::string_view text);

// A byte count: a number with an optional binary suffix K, M, G or T, in either case
// (1K = 1024 bytes): "512M", "8g", "100000". Negative sizes are refused.
std::optional<double> parse_size(std::string_view text);
// A byte count for people, one decimal: "0.5 KiB", "3.2 MiB", "2.0 GiB".
std::string format_bytes(uint64_t bytes);

// `s` cut at every `sep`; a trailing separator gives a final empty part, an empty `s` none.
std::vector<std::string> split(const std::string& s, char sep);
// The parts joined with `sep` between them.
std::string join(const std::vector<std::string>& parts, const std::string& sep = ", ");

}  // namespace multiray
