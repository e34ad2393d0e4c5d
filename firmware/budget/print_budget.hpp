#pragma once
// Prints the board's buffer table and storage budget (fw::buffer_budget, fw::storage_budget)
// to a stream, one line each: what amb-firmware logs when it starts.
#include <cstdio>
#include <vector>

#include "firmware/budget/board_budget.hpp"

namespace amb::fw {

void print_budget(std::FILE* out, const std::vector<BufferBudget>& table, const StorageBudget& storage);

}  // namespace amb::fw
