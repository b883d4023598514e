#include "write/mesh/face_formatter.h"

namespace mvox {

FormattedRecords& FaceFormatter::records() {
  if (!records_) throw Error(subject(), "internal error: faces formatted with nowhere to go");
  return *records_;
}

}  // namespace mvox
