//! Geometry: points in d dimensions, local frames, convex hulls, enclosing balls.

mod axis_frame;
mod enclosing_ball;
mod hull;
mod hull3d;
mod point;

pub use axis_frame::{AxisFrame, MAX_DIM};
pub use enclosing_ball::{Ball, enclosing_ball, enclosing_radius};
pub use hull::{HullGeometry, convex_hull_2d, convex_hull_2d_all, polygon_area};
pub use hull3d::convex_hull_3d;
pub use point::{Point, angle_between};
