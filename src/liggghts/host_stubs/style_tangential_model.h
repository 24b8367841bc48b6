// Empty stand-in for LIGGGHTS' generated tangential-model style list (not shipped by libliggghts-dev).
// fracdem only calls public accessors of FixWallGran; the TANGENTIAL_MODEL constants are never used,
// and class layouts do not depend on them.
