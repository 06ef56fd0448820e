// Agreement at the end of each phase of a tiled job: every rank learns whether any
// failed, and the first failing rank's error becomes every rank's (a failing rank
// stops the job cleanly instead of leaving the others waiting in a collective).
#pragma once
#include <pcl_vts/core/status.h>
#include <pcl_vts/tiling/job_comm.h>

namespace pcl_vts {

/// Collective. Success when every rank's `mine` is; else the error of the lowest
/// failing rank, prefixed with "rank R: " when there are several ranks.
Status agree(JobComm& comm, const Status& mine);

} // namespace pcl_vts
