//! Tukey box plots: a box from the first to the third quartile with the median across
//! it, whiskers to the most extreme values within 1.5 interquartile ranges of the box,
//! and the values beyond the whiskers drawn one by one.
//!
//! (plotters' own `Boxplot` draws its whiskers at the fences themselves, wherever the
//! data are: below 0 for a ratio that cannot be, beyond every value of a tight sample.)

use plotters::element::{Drawable, PointCollection};
use plotters::style::ShapeStyle;
use plotters_backend::{BackendCoord, DrawingBackend, DrawingErrorKind};

use monoculus_experiments::results::quantile;

/// What a box shows of a sample.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BoxSummary {
    /// The lowest value at or above the lower fence (Q1 - 1.5 IQR).
    pub low: f64,
    /// First quartile, median and third quartile (numpy's default interpolation, as in
    /// `summary.csv`).
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    /// The highest value at or below the upper fence (Q3 + 1.5 IQR).
    pub high: f64,
    /// The values beyond the whiskers.
    pub outliers: Vec<f64>,
}

impl BoxSummary {
    /// The summary of the finite values of `values`; `None` if there are none.
    pub fn of(values: &[f64]) -> Option<Self> {
        let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        if finite.is_empty() {
            return None;
        }
        let (q1, median, q3) = (
            quantile(&finite, 0.25),
            quantile(&finite, 0.5),
            quantile(&finite, 0.75),
        );
        let iqr = q3 - q1;
        let (lower_fence, upper_fence) = (q1 - 1.5 * iqr, q3 + 1.5 * iqr);
        let inside = |v: &f64| (lower_fence..=upper_fence).contains(v);
        // The quartiles lie between the sample's extremes, so some value is inside.
        let low = finite.iter().copied().filter(inside).fold(q1, f64::min);
        let high = finite.iter().copied().filter(inside).fold(q3, f64::max);
        let outliers = finite.iter().copied().filter(|v| !inside(v)).collect();
        Some(BoxSummary {
            low,
            q1,
            median,
            q3,
            high,
            outliers,
        })
    }
}

/// A vertical box of a [`BoxSummary`] at `key` on the x axis, `offset` pixels to the
/// side (several series side by side).
pub(crate) struct TukeyBox<K> {
    key: K,
    /// low, q1, median, q3, high, then the outliers.
    values: Vec<f32>,
    style: ShapeStyle,
    width: u32,
    whisker_width: f64,
    offset: f64,
}

impl<K> TukeyBox<K> {
    pub fn new(key: K, summary: &BoxSummary, style: ShapeStyle, width: u32, offset: f64) -> Self {
        let s = summary;
        let values = [s.low, s.q1, s.median, s.q3, s.high]
            .into_iter()
            .chain(s.outliers.iter().copied())
            .map(|v| v as f32)
            .collect();
        TukeyBox {
            key,
            values,
            style,
            width,
            whisker_width: 0.6,
            offset,
        }
    }
}

impl<'a, K: Clone> PointCollection<'a, (K, f32)> for &'a TukeyBox<K> {
    type Point = (K, f32);
    type IntoIter = Vec<(K, f32)>;

    fn point_iter(self) -> Self::IntoIter {
        self.values.iter().map(|&v| (self.key.clone(), v)).collect()
    }
}

impl<K, DB: DrawingBackend> Drawable<DB> for TukeyBox<K> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        points: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let points: Vec<BackendCoord> = points.collect();
        if points.len() < 5 {
            return Ok(());
        }
        let shift = |(x, y): BackendCoord, dx: f64| (x + (self.offset + dx) as i32, y);
        let half = f64::from(self.width) / 2.0;
        let whisker = half * self.whisker_width;
        let (low, q1, median, q3, high) = (points[0], points[1], points[2], points[3], points[4]);
        // Whisker caps and stems.
        for (end, edge) in [(low, q1), (high, q3)] {
            backend.draw_line(shift(end, -whisker), shift(end, whisker), &self.style)?;
            backend.draw_line(shift(end, 0.0), shift(edge, 0.0), &self.style)?;
        }
        // The box and the median.
        let (a, b) = (shift(q3, -half), shift(q1, half));
        let upper_left = (a.0.min(b.0), a.1.min(b.1));
        let bottom_right = (a.0.max(b.0), a.1.max(b.1));
        backend.draw_rect(upper_left, bottom_right, &self.style, false)?;
        backend.draw_line(shift(median, -half), shift(median, half), &self.style)?;
        // The values beyond the whiskers.
        for &p in &points[5..] {
            backend.draw_circle(shift(p, 0.0), 3, &self.style, false)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whiskers_end_at_values_and_far_values_are_outliers() {
        // Quartiles 2 and 4 (IQR 2, fences -1 and 7): 100 is beyond, and the low
        // whisker ends at the lowest value, 1, not at the fence.
        let s = BoxSummary::of(&[1.0, 2.0, 3.0, 4.0, 5.0, 100.0, 3.0, 2.0, 4.0]).unwrap();
        assert_eq!((s.q1, s.median, s.q3), (2.0, 3.0, 4.0));
        assert_eq!((s.low, s.high), (1.0, 5.0));
        assert_eq!(s.outliers, vec![100.0]);
    }

    #[test]
    fn a_positive_sample_has_no_whisker_below_its_least_value() {
        // plotters put this lower whisker at 1.0 - 1.5 * 1.0 = -0.5.
        let s = BoxSummary::of(&[1.0, 1.0, 1.5, 2.0, 2.0]).unwrap();
        assert_eq!((s.low, s.high), (1.0, 2.0));
        assert!(s.outliers.is_empty());
    }

    #[test]
    fn the_quartiles_are_those_of_the_summary_file_and_nan_is_left_out() {
        let values = [0.3, f64::NAN, 7.0, 1.1, 2.5, 9.0, 4.2];
        let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        let s = BoxSummary::of(&values).unwrap();
        assert_eq!(s.q1, quantile(&finite, 0.25));
        assert_eq!(s.median, quantile(&finite, 0.5));
        assert_eq!(s.q3, quantile(&finite, 0.75));
        assert_eq!(BoxSummary::of(&[f64::NAN]), None);
        let one = BoxSummary::of(&[2.0]).unwrap();
        assert_eq!(
            (one.low, one.q1, one.median, one.q3, one.high),
            (2.0, 2.0, 2.0, 2.0, 2.0)
        );
    }
}
