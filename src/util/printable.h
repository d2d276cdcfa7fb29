#pragma once
// Text from outside (file names, movie tags, preset keys and values) may hold control
// characters: an escape sequence printed raw would drive the user's terminal, a newline written
// into a script comment would end it. printable() shows each as \xNN.
#include <string>
#include <string_view>

namespace pluvia {

// Every byte below 0x20 and 0x7f as "\xNN", except newlines and tabs when keepLines (for
// messages of several lines); everything else (UTF-8 included) as it is.
std::string printable(std::string_view text, bool keepLines = false);

}  // namespace pluvia
