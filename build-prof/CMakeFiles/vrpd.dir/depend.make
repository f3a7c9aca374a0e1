# Empty dependencies file for vrpd.
# This may be replaced when dependencies are built.
