"""The robot catalog, the makers' conventions and the tool library: data only; imports core/, errors, dependencies and command_line."""
