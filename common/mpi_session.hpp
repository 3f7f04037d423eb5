// An MPI job as one process sees it (built only when MPI is found): MPI_Init_thread on construction,
// MPI_Finalize on destruction, this rank and the number of ranks, and the few collectives the
// commands share. MPI calls are made by one thread at a time per rank (MPI_THREAD_SERIALIZED).
#pragma once

namespace grainbank::common {

class MpiSession {
 public:
  // True when this process was started by mpirun/mpiexec (so MPI must be initialised).
  static bool launched_by_mpirun();
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Every rank learns whether all ranks passed (logical and).
  bool all(bool ok) const;
  void barrier() const;

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace grainbank::common
