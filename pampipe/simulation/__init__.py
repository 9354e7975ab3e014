"""Forward simulation: a muscle anchored in pipes, and synthetic experiments that follow the protocol."""
