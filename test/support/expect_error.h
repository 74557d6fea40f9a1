/*
 * pcl_texlet tests: checking that bad input gets an exception of the right type whose message
 * names the input and the problem.
 */
#pragma once

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <utility>

namespace pcl_texlet_test
{

/** \brief Runs \a f, expecting an exception of type E whose message holds every one of \a needles
  * (another type escapes, and fails the test).
  */
template <typename E = pcl::IOException, typename F> void
expectError (F &&f, std::initializer_list<std::string> needles)
{
  try
  {
    f ();
  }
  catch (const E &e)
  {
    const std::string message = e.what ();
    for (const std::string &needle : needles)
      EXPECT_NE (message.find (needle), std::string::npos) << "'" << needle << "' not in: " << message;
    return;
  }
  std::string expected;
  for (const std::string &needle : needles)
    expected += " '" + needle + "'";
  ADD_FAILURE () << "no exception of the expected type thrown; expected one with" << expected;
}

/** \brief expectError with two needles: typically the input's name and the problem. */
template <typename E, typename F> void
expectError (F &&f, const std::string &a, const std::string &b)
{
  expectError<E> (std::forward<F> (f), {a, b});
}

} // namespace pcl_texlet_test
