# Empty dependencies file for vrpd_cli.
# This may be replaced when dependencies are built.
