#pragma once
// Seed 002 Table 2: the three elliptical wears the journal-bearing tests identify.
namespace amb::test::journal {

struct Table2Wear {
  const char* name;   ///< "wear 1" .. "wear 3", for messages
  const char* tag;    ///< "w1" .. "w3", for file names
  double d0_um;       ///< wear depth, um
  double gamma_deg;   ///< wear angular position, deg
  double beta_deg;    ///< wear angular extent, deg
};

inline constexpr Table2Wear k_table2_wears[] = {{"wear 1", "w1", 46.5, 23.0, 77.0},
                                                {"wear 2", "w2", 98.28, 5.1, 74.0},
                                                {"wear 3", "w3", 15.02, 19.0, 102.0}};

}  // namespace amb::test::journal
