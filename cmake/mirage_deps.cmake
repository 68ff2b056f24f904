# Every third-party dependency, found in one place. All come from Debian 12 packages
# (scripts/install-deps installs them); nothing is downloaded at configure time.
find_package(Threads REQUIRED)
find_package(embree 3.13 REQUIRED)          # libembree-dev: ray casting
find_package(Eigen3 3.4 REQUIRED NO_MODULE) # libeigen3-dev: vectors, quaternions
find_package(yaml-cpp REQUIRED)             # libyaml-cpp-dev: scene and sensor files
list(APPEND CMAKE_MODULE_PATH /usr/share/cmake/geographiclib)
find_package(GeographicLib REQUIRED)        # libgeographiclib-dev: WGS84 <-> local frames
if(NOT TARGET GeographicLib::GeographicLib)
  add_library(GeographicLib::GeographicLib INTERFACE IMPORTED)
  target_include_directories(GeographicLib::GeographicLib INTERFACE ${GeographicLib_INCLUDE_DIRS})
  target_link_libraries(GeographicLib::GeographicLib INTERFACE ${GeographicLib_LIBRARIES})
endif()
find_package(PROJ REQUIRED CONFIG)          # libproj-dev: EPSG -> WKT, projected <-> geodetic
find_package(CLI11 REQUIRED)                # libcli11-dev: command line
find_package(fmt REQUIRED)                  # libfmt-dev: formatting
find_package(PNG REQUIRED)                  # libpng-dev: preview images
find_package(PCL 1.13 QUIET COMPONENTS common io)  # libpcl-dev: an independent Velodyne client
find_package(PkgConfig REQUIRED)
pkg_check_modules(PCAP REQUIRED IMPORTED_TARGET libpcap)  # libpcap-dev: pcap capture files
pkg_check_modules(LZMA REQUIRED IMPORTED_TARGET liblzma)  # liblzma-dev: CRC-64/XZ (Ouster), CRC-32 (NovAtel)
pkg_check_modules(LIBUSB REQUIRED IMPORTED_TARGET libusb-1.0)  # libusb-1.0-0-dev: gs_usb CAN adapters
pkg_check_modules(MODBUS REQUIRED IMPORTED_TARGET libmodbus)  # libmodbus-dev: the rig's control plane (Modbus TCP/RTU)
find_package(nlohmann_json 3.11 REQUIRED)  # nlohmann-json3-dev: Ouster metadata, reports
find_package(Boost 1.74 REQUIRED)           # libboost-dev: Boost.Asio (header-only) UDP sockets
if(MIRAGE_BUILD_TESTS)
  find_package(GTest REQUIRED)              # googletest
  find_package(benchmark REQUIRED)          # libbenchmark-dev
  # librandom123-dev: the reference Philox the tests hold Mirage's generator against.
  find_path(RANDOM123_INCLUDE_DIR Random123/philox.h REQUIRED)
endif()
