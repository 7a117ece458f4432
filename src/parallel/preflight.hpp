// Checks made before a run creates its file, and the I/O error told after: the memory one
// sample's results take on each rank, the disk the file takes, and what to do when writing fails.
#pragma once
#include <exception>
#include <string>

#include "io/run_file.hpp"
#include "parallel/ensemble.hpp"
#include "study/setup.hpp"

namespace kanesens::parallel::detail {

// Rows of consecutive samples wait in a block to be written together; the block is written
// early once it holds this many bytes, so that its memory stays bounded whatever the chunk.
constexpr double kBlockBytes = 32.0 * (1 << 20);

// Bytes the run file will take on disk (every per-sample dataset is allocated when the file is
// created).
double estimate_file_bytes(const io::RunLayout& l);

// Checks that `ranks_here` ranks on one node can each hold a sample's results. Returns the
// InputError line or "".
std::string check_memory(const io::RunLayout& l, const study::StudySpec& st, int ranks_here);

// Rank 0's check that the output can be written (directory, existing file, free space).
// Returns the InputError line or "".
std::string check_output(const std::string& output, const RunOptions& opt, const io::RunLayout& layout,
                         const study::StudySpec& st, int ranks_here);

// Rethrows an I/O error with what the user can do about it. `need`: estimated bytes of the file
// being created (0 once it exists).
[[noreturn]] void rethrow_io_error(const std::exception& e, const std::string& output, const std::string& study,
                                   double need);

}  // namespace kanesens::parallel::detail
