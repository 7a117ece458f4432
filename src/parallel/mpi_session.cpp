#include "parallel/mpi_session.hpp"

#include <exception>
#include <stdexcept>

namespace kanesens::parallel {

void check_mpi(int rc, const char* call) {
  if (rc == MPI_SUCCESS) return;
  char msg[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, msg, &len);
  throw std::runtime_error(std::string("MPI call ") + call + " failed: " + std::string(msg, static_cast<std::size_t>(len)));
}

MpiSession::MpiSession(int* argc, char*** argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    check_mpi(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    owns_ = true;
  }
  // Errors come back as return codes, which check_mpi turns into exceptions with context.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (owns_ && !finalized) MPI_Finalize();
}

SharedCounter::SharedCounter(MPI_Comm comm, long long initial) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const MPI_Aint bytes = rank == 0 ? static_cast<MPI_Aint>(sizeof(long long)) : 0;
  check_mpi(MPI_Win_allocate(bytes, sizeof(long long), MPI_INFO_NULL, comm, &base_, &win_), "MPI_Win_allocate");
  if (rank == 0) {
    check_mpi(MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, win_), "MPI_Win_lock");
    *base_ = initial;
    check_mpi(MPI_Win_unlock(0, win_), "MPI_Win_unlock");
  }
  check_mpi(MPI_Barrier(comm), "MPI_Barrier");
}

SharedCounter::~SharedCounter() {
  // MPI_Win_free is collective: while an exception unwinds this rank alone (the others may be
  // mid-sample), freeing would wait forever; the caller aborts the job instead.
  if (win_ != MPI_WIN_NULL && std::uncaught_exceptions() == 0) MPI_Win_free(&win_);
}

long long SharedCounter::fetch_add(long long amount) {
  long long old = 0;
  check_mpi(MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, win_), "MPI_Win_lock");
  check_mpi(MPI_Fetch_and_op(&amount, &old, MPI_LONG_LONG, 0, 0, MPI_SUM, win_), "MPI_Fetch_and_op");
  check_mpi(MPI_Win_unlock(0, win_), "MPI_Win_unlock");
  return old;
}

long long SharedCounter::read() {
  long long v = 0, zero = 0;
  check_mpi(MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, win_), "MPI_Win_lock");
  check_mpi(MPI_Fetch_and_op(&zero, &v, MPI_LONG_LONG, 0, 0, MPI_NO_OP, win_), "MPI_Fetch_and_op");
  check_mpi(MPI_Win_unlock(0, win_), "MPI_Win_unlock");
  return v;
}

}  // namespace kanesens::parallel
