#include "db/sqlite/store_path.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace tinbase {

namespace {

std::string DirectoryOf(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

bool Exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

// Why stat() failed on the store path, for an existing path's ancestors or the path itself.
Status StatProblem(const std::string& path, int errnum, Connection::Mode mode) {
  switch (errnum) {
    case ENOENT:
      if (mode == Connection::Mode::kCreate) return Status::Ok();
      return Status::NotFound(path + ": no such store");
    case ENAMETOOLONG:
      return Status::InvalidArgument(path.substr(0, 60) + "...: the path is too long (" +
                                     std::to_string(path.size()) + " bytes)");
    case EACCES:
      return Status::InvalidArgument(path +
                                     ": permission denied (a directory on the way cannot "
                                     "be searched)");
    case ENOTDIR:
      return Status::InvalidArgument(path + ": a part of the path is not a directory");
    case ELOOP:
      return Status::InvalidArgument(path + ": too many symbolic links on the way");
    default:
      return Status::InvalidArgument(path + ": " + DescribeSystemError(errnum));
  }
}

// Why a store cannot be created in `dir`, from access(2)'s errno: the directory may be missing
// or read-only rather than forbidden.
Status CreateProblem(const std::string& path, const std::string& dir, int errnum) {
  std::string why = "permission denied in its directory " + dir;
  if (errnum == ENOENT) why = "there is no directory " + dir;
  if (errnum == ENOTDIR) why = dir + " is not a directory";
  if (errnum == EROFS) why = "its directory " + dir + " is on a read-only file system";
  return Status::InvalidArgument(path + ": cannot create the store: " + why);
}

}  // namespace

std::string DescribeSystemError(int errnum) {
  switch (errnum) {
    case 0:
      return "";
    case ENOSPC:
      return "no space left on the device";
    case EACCES:
    case EPERM:
      return "permission denied";
    case EROFS:
      return "the file system is read-only";
    case EISDIR:
      return "is a directory";
    case EDQUOT:
      return "disk quota exceeded";
    default:
      return std::strerror(errnum);
  }
}

Status StorePathProblem(const std::string& path, Connection::Mode mode) {
  if (path.empty()) return Status::InvalidArgument("the store path is empty");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int errnum = errno;
    TB_RETURN_IF_ERROR(StatProblem(path, errnum, mode));
  } else if (mode == Connection::Mode::kCreate) {
    return Status::InvalidArgument(path + ": a file already exists there");
  } else if (S_ISDIR(st.st_mode)) {
    return Status::InvalidArgument(path + ": is a directory, not a store");
  } else if (!S_ISREG(st.st_mode)) {
    return Status::InvalidArgument(path + ": is not a regular file");
  }
  const std::string dir = DirectoryOf(path);
  const bool dir_writable = ::access(dir.c_str(), W_OK | X_OK) == 0;
  const int dir_errno = dir_writable ? 0 : errno;
  switch (mode) {
    case Connection::Mode::kCreate:
      if (!dir_writable) return CreateProblem(path, dir, dir_errno);
      return Status::Ok();
    case Connection::Mode::kReadWrite:
      if (::access(path.c_str(), R_OK | W_OK) != 0)
        return Status::InvalidArgument(path +
                                       ": permission denied: the store is not writable by "
                                       "this user (commands that only read still work)");
      if (!dir_writable)
        return Status::InvalidArgument(path + ": permission denied: its directory " + dir +
                                       " is not writable, and a write needs to create " + path +
                                       "-wal and " + path + "-shm there");
      return Status::Ok();
    case Connection::Mode::kReadOnly:
      if (::access(path.c_str(), R_OK) != 0)
        return Status::InvalidArgument(path +
                                       ": permission denied: the store is not readable by "
                                       "this user");
      if (!dir_writable && !Exists(path + "-shm"))
        return Status::InvalidArgument(path + ": permission denied: its directory " + dir +
                                       " is not writable, and even a reader needs to create " +
                                       path +
                                       "-shm there (open it once where it may, or copy "
                                       "the store)");
      return Status::Ok();
  }
  return Status::Ok();
}

}  // namespace tinbase
