#pragma once
// The OpenIGTLink library's headers for the tests' loopback clients (they do not pass our
// -Wshadow -Wconversion). A test using it calls trocar_test_link_openigtlink() in CMake.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlPositionMessage.h>
#include <igtlSensorMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_header.h>  // raw headers for the malformed-message tests
#include <igtl_util.h>
#pragma GCC diagnostic pop
