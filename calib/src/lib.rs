//! Odometry calibration math.
