#pragma once
// Number and JSON formatting shared by the writers in io/. Locale-independent, and exact: a double
// printed here parses back to the same bits, so two output files compare equal iff the runs did.
#include <nlohmann/json.hpp>

#include <string>

namespace rbpart {

// Shortest decimal text that parses back to exactly `value`, laid out as %g: "0.1", "0.0005",
// "1e-06", "-0", "inf".
std::string round_trip(double value);

// Text from an input file as an error message quotes it: control bytes as \xNN, so that a binary
// file's NUL does not cut the message short and its other control bytes do not reach the terminal.
std::string printable(const std::string& text);

// Indented JSON that stays readable for geometry: arrays of scalars (vectors, quaternions) and
// small flat objects on one line, everything else one member per line. Numbers round-trip.
std::string pretty_json(const nlohmann::ordered_json& value);

}  // namespace rbpart
