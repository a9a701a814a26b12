#pragma once
// Precompiled for every gtest (CMakeLists.txt, wp_add_gtest; -DWP_NO_PCH=ON leaves it out): the
// headers nearly all of them parse, gtest and Eigen most of all (about 2-3 s of each test
// source's compile on a 2-core VM). Only third-party and standard headers: a test's own
// includes still say what it uses.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
