#pragma once
// The command line's view of the hybrid model's files: a record given as
// "FILE.mat,state=S,rpm=R,load=L[,fs=HZ][,var=NAME]" and the CSV of a prediction.
#include <string>

#include "host-tools/core/hybrid/hybrid_model.hpp"

namespace amb::host::hybrid {

/// Parse "PATH[,key=value]..." (keys state, rpm, load, fs, var). `need_condition`: state, rpm
/// and load are required (a training record); otherwise they are refused (a measured record
/// to score). The signal is not loaded (load_record()). Throws std::invalid_argument naming
/// the spec and what is wrong, or the missing file.
Record parse_record_spec(const std::string& spec, bool need_condition);

/// Write the predicted spectra as CSV: a comment line with the units, then one row per bin:
/// spectrum (log_psd | envelope), f_hz, hybrid, hybrid_lo, hybrid_hi, physics, data_only,
/// nearest_transport, interpolated_transport (empty cells where a baseline has no prediction).
/// Throws std::runtime_error naming the path if it cannot be written.
void write_prediction_csv(const Prediction& p, const std::string& path);

}  // namespace amb::host::hybrid
