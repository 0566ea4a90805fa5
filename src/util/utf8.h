// Text that is bytes: Linux file names (and so scene, --out and --trace paths) are any
// bytes but '/' and NUL, while JSON and the viewer's pages need valid UTF-8. A name is
// recorded with each byte that is not part of valid UTF-8 written as the four characters
// "\xHH", so a record stays readable and says which bytes the name had.
#pragma once

#include <string>
#include <string_view>

namespace multiray {

// The length of the valid UTF-8 sequence starting at text[i], or 0 if it is not one
// (overlong forms, surrogates and code points above U+10FFFF are invalid, as RFC 3629 says).
size_t utf8_sequence_length(std::string_view text, size_t i);

// True when `text` is valid UTF-8 (RFC 3629).
bool is_valid_utf8(std::string_view text);

// `text` with every byte outside a valid UTF-8 sequence replaced by "\xHH" (upper-case
// hex). Valid text is returned unchanged.
std::string escape_invalid_utf8(std::string_view text);

}  // namespace multiray
