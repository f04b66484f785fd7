find_package(Ceres 2.1 REQUIRED)
