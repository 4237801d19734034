"""The robot catalog, the makers' conventions and the tool library: data only; imports core/, errors and dependencies."""
