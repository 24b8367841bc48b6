// Empty stand-in for LIGGGHTS' generated rolling-model style list (not shipped by libliggghts-dev).
// fracdem only calls public accessors of FixWallGran; the ROLLING_MODEL constants are never used,
// and class layouts do not depend on them.
