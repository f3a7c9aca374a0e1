file(REMOVE_RECURSE
  "libvrpd.a"
)
