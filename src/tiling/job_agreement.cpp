// Phase agreement (job_agreement.h).
#include "job_agreement.h"

#include <algorithm>
#include <string>
#include <vector>

namespace pcl_vts {

Status agree(JobComm& comm, const Status& mine)
{
  std::vector<std::uint64_t> failed(static_cast<std::size_t>(comm.size()), 0);
  failed[static_cast<std::size_t>(comm.rank())] = mine.ok() ? 0 : 1;
  comm.sum(failed);
  const auto first = std::find(failed.begin(), failed.end(), 1u);
  if (first == failed.end())
    return Status::success();
  const int root = static_cast<int>(first - failed.begin());
  std::string bytes;
  if (comm.rank() == root)
    bytes = std::to_string(static_cast<int>(mine.code)) + " " + mine.message;
  comm.broadcast(bytes, root);
  const std::size_t space = bytes.find(' ');
  const auto code = static_cast<StatusCode>(std::stoi(bytes.substr(0, space)));
  const std::string message = bytes.substr(space + 1);
  return Status::error(code, comm.size() > 1
                                 ? "rank " + std::to_string(root) + ": " + message
                                 : message);
}

} // namespace pcl_vts
