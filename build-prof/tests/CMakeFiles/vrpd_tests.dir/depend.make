# Empty dependencies file for vrpd_tests.
# This may be replaced when dependencies are built.
