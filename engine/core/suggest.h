#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace caustica {

// The candidate closest to `name` by edit distance, or "" when none is close enough to be a typo.
std::string nearest_name(std::string_view name, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" — ready to append to a message.
std::string did_you_mean(std::string_view name, const std::vector<std::string>& candidates);

}  // namespace caustica
