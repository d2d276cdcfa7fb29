#pragma once
// A preset's dotted key paths ("rain.wind.speed_m_s"), split into their parts: what the preset's
// loader, its overrides and its schema check (preset_validation.cpp) all walk.
#include <string>
#include <vector>

namespace pluvia {

// "a.b.c" -> {"a", "b", "c"}; "" -> {""}.
std::vector<std::string> splitDots(const std::string& path);

}  // namespace pluvia
