/*
 * pcl_texlet model lab (internal): every combination of a term's settings to try, for the searches
 * over a distortion map's shapes (linearBiasShapeSearch) and a term's forms (formSearch).
 */
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** The settings to try, each with its values (none empty). */
using SettingSearch = std::vector<std::pair<std::string, std::vector<double>>>;

/** One value for each setting of a search. */
using SettingCombination = std::vector<std::pair<std::string, double>>;

/** Calls \a visit with every combination of the values in \a search (an odometer over their
  * lists), first setting first; once, with no setting, when \a search is empty.
  */
template <typename Visit>
void
forEachSettingCombination (const SettingSearch &search, Visit visit)
{
  std::vector<std::size_t> at (search.size (), 0);
  for (;;)
  {
    SettingCombination combination;
    for (std::size_t k = 0; k < search.size (); ++k)
      combination.emplace_back (search[k].first, search[k].second[at[k]]);
    visit (combination);
    std::size_t k = 0;
    while (k < search.size () && ++at[k] == search[k].second.size ())
      at[k++] = 0;
    if (k == search.size ())
      return;
  }
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
