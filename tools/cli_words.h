// The words of the tools' command lines turned into the libraries' typed settings:
// the libraries take a DuplicateRule, a LasReturnFilter, a list of class codes, and
// never see the text a user typed.
#pragma once

#include <pcl_vts/core/merge_duplicates.h>
#include <pcl_vts/io/las_reader.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {
namespace tools {

/// "lowest" | "highest" | "mean" | "first" (duplicateRuleName's words); false on
/// anything else.
bool parseDuplicateRule(const std::string& word, DuplicateRule& rule);

/// "all" | "first" | "last" (lasReturnFilterName's words); false on anything else.
bool parseLasReturnFilter(const std::string& word, LasReturnFilter& filter);

/// The whole text is one finite number (strtod's syntax, no leading blank).
bool parseFiniteNumber(const std::string& text, double& value);

/// Exactly `count` comma-separated finite numbers ("X0,Y0,X1,Y1").
bool parseNumberList(const std::string& text, std::size_t count,
                     std::vector<double>& numbers);

/// A classification list "2" or "2,9", each code 0-255, repeats kept once, in order.
/// False with error naming the bad item ("'300' in '2,300' is not a class code ...").
bool parseClassList(const std::string& text, std::vector<std::uint8_t>& classes,
                    std::string& error);

} // namespace tools
} // namespace pcl_vts
