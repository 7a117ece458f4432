// RAII for MPI_Init_thread/MPI_Finalize, and a checked-call helper. Only `kanesens run`
// starts MPI; the other commands run without it.
#pragma once
#include <mpi.h>

#include <string>

namespace kanesens::parallel {

class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  bool owns_ = false;
  int rank_ = 0, size_ = 1;
};

// Throws std::runtime_error naming `call` when rc != MPI_SUCCESS.
void check_mpi(int rc, const char* call);

// A shared counter on rank 0 that any rank can atomically advance without rank 0's help
// (MPI one-sided MPI_Fetch_and_op, passive target). Collective constructor and destructor.
class SharedCounter {
 public:
  SharedCounter(MPI_Comm comm, long long initial);
  ~SharedCounter();
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;
  // Adds `amount` and returns the value before the addition.
  long long fetch_add(long long amount);
  long long read();

 private:
  MPI_Win win_ = MPI_WIN_NULL;
  long long* base_ = nullptr;
};

}  // namespace kanesens::parallel
