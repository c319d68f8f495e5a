// Apple XML property lists, as InVesalius writes them (core/io/plist.cpp).
#include "fuzz_common.h"
#include "io/plist.h"

MPUMESH_FUZZ_TARGET(mpumesh::plist::parse(bytes, "fuzz.plist"))
