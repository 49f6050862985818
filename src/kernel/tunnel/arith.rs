//! The arithmetic of the tunnel sweep ([`super`]): one trait, [`Num`], for
//! the number types it runs on, and the two rounded types whose comparisons
//! know when their sign is in doubt ([`Filtered`], [`Unit`]), with the
//! three-valued truth ([`Maybe`]) those comparisons give. The sweep itself
//! is written once, generic over [`Num`]; the error bounds that make the
//! rounded types sure are proved here, in their docs.

use bnum::types::{I1024, I256, I512};
use std::convert::Infallible;
use std::hint::select_unpredictable;
use std::ops::{Add, BitAnd, BitOr, Mul, Neg, Not, Sub};

/// Arithmetic the sweep needs: exact for the integer types, rounded for
/// `f64`, and rounded with an error bound for [`Filtered`], whose
/// comparisons say when their sign is in doubt.
pub(super) trait Num:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// What a comparison gives: `bool`, or [`Maybe`] for a type that can
    /// be in doubt.
    type Bool: Logic<Doubt = Self::Doubt>;
    /// What a sweep gives up with: [`Infallible`] for a type never in doubt.
    type Doubt;
    const ZERO: Self;
    const ONE: Self;
    const TWO: Self;
    const FOUR: Self;
    /// `self < other`, or `self <= other` if `or_equal`.
    fn below(self, other: Self, or_equal: bool) -> Self::Bool;
    /// `x` if `c`, else `y`, without a branch.
    fn select(c: Self::Bool, x: Self, y: Self) -> Self;
    /// [`is_in`] of one of the sweep's inputs (a cell value, or its
    /// negation), whose sign is never in doubt.
    #[inline(always)]
    fn input_in(self, closed: bool) -> Self::Bool {
        is_in(self, closed)
    }
}

/// The truth values of comparisons, combined without branches.
pub(super) trait Logic:
    Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self>
{
    /// See [`Num::Doubt`].
    type Doubt;
    /// The value as a `bool`, unless it is in doubt.
    fn decided(self) -> Result<bool, Self::Doubt>;
}

impl Logic for bool {
    type Doubt = Infallible;
    fn decided(self) -> Result<bool, Infallible> {
        Ok(self)
    }
}

/// Implements [`Num`] for a type whose comparisons are taken at their word.
macro_rules! plain_num {
    ($t:ty, $zero:expr, $one:expr, $two:expr, $four:expr) => {
        impl Num for $t {
            type Bool = bool;
            type Doubt = Infallible;
            const ZERO: Self = $zero;
            const ONE: Self = $one;
            const TWO: Self = $two;
            const FOUR: Self = $four;
            #[inline(always)]
            fn below(self, other: Self, or_equal: bool) -> bool {
                (self < other) | (or_equal & (self == other))
            }
            #[inline(always)]
            fn select(c: bool, x: Self, y: Self) -> Self {
                select_unpredictable(c, x, y)
            }
        }
    };
}

plain_num!(i64, 0, 1, 2, 4);
plain_num!(i128, 0, 1, 2, 4);
plain_num!(I256, I256::ZERO, I256::ONE, I256::TWO, I256::FOUR);
plain_num!(I512, I512::ZERO, I512::ONE, I512::TWO, I512::FOUR);
plain_num!(I1024, I1024::ZERO, I1024::ONE, I1024::TWO, I1024::FOUR);
plain_num!(f64, 0.0, 1.0, 2.0, 4.0);

/// An `f64` computed from integer values by `+`, `-` and `*`, with the
/// same expression evaluated on the magnitudes (`m`, each product's and
/// sum's terms taken positive). Each input is an integer rounded to a
/// double (exact unless it needs more than 53 bits). In the expanded
/// polynomial each term carries one factor `1 + δ`, `|δ| <= 2^-53`, per
/// rounding it went through and per rounded input in it: a product's terms
/// carry the factors of both operands. That is at most [`MAX_ROUNDINGS`]
/// factors, so the rounded value differs from the exact one by at most
/// `γ_16 m`, about `2^-49 m` (Higham, Accuracy and Stability of Numerical
/// Algorithms, 3.1); `m` itself is rounded down by at most a factor
/// `(1 - 2^-53)^16`. The integers have at most [`WIDEST_BITS`](super::WIDEST_BITS) bits, so no
/// product underflows or overflows, and every rounded value is an integer
/// too (a double of magnitude at least 2^53 is one): a bound below 1/2
/// means the value is exact (an input that was rounded has a magnitude of
/// at least 2^53, and so has every nonzero term it enters).
#[derive(Clone, Copy, Debug)]
pub(super) struct Filtered {
    v: f64,
    m: f64,
}

/// The most factors `1 + δ` a term of the sweep carries: `qb * qb - 4 qa
/// qc` (`qb` is five roundings deep: a difference of values, a product and
/// three sums; squared and subtracted, 12) with its four rounded inputs.
/// `value_at`'s `qb p q` and the sums after it carry at most 15.
pub(super) const MAX_ROUNDINGS: u32 = 16;

impl Filtered {
    /// An input: an integer, rounded to a double.
    pub(super) fn input(v: f64) -> Self {
        Filtered { v, m: v.abs() }
    }
}

impl Add for Filtered {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Filtered {
            v: self.v + o.v,
            m: self.m + o.m,
        }
    }
}

impl Sub for Filtered {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Filtered {
            v: self.v - o.v,
            m: self.m + o.m,
        }
    }
}

impl Mul for Filtered {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Filtered {
            v: self.v * o.v,
            m: self.m * o.m,
        }
    }
}

impl Neg for Filtered {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Filtered {
            v: -self.v,
            m: self.m,
        }
    }
}

impl Num for Filtered {
    type Bool = Maybe;
    type Doubt = Doubt;
    const ZERO: Self = Filtered { v: 0.0, m: 0.0 };
    const ONE: Self = Filtered { v: 1.0, m: 1.0 };
    const TWO: Self = Filtered { v: 2.0, m: 2.0 };
    const FOUR: Self = Filtered { v: 4.0, m: 4.0 };

    /// The rounded comparison, sure when the values are further apart than
    /// their error bounds (`2^-46 m`, about 8 times what [`Filtered`] proves,
    /// which covers this test's own roundings), or when the bounds are
    /// below 1/2 (then both values are exact).
    #[inline(always)]
    fn below(self, o: Self, or_equal: bool) -> Maybe {
        const _: () = assert!(MAX_ROUNDINGS <= 16, "the error bound assumes 16 factors");
        const ERROR: f64 = 1.0 / (1u64 << 46) as f64;
        let bound = (self.m + o.m) * ERROR;
        Maybe {
            value: (self.v < o.v) | (or_equal & (self.v == o.v)),
            sure: ((self.v - o.v).abs() > bound) | (bound < 0.5),
        }
    }

    /// A choice in doubt gives a value whose bound is infinite, so that
    /// every comparison it enters is in doubt (`∞ * 0`, NaN, compares
    /// false too).
    #[inline(always)]
    fn select(c: Maybe, x: Self, y: Self) -> Self {
        let chosen = select_unpredictable(c.value, x, y);
        Filtered {
            v: chosen.v,
            m: select_unpredictable(c.sure, chosen.m, f64::INFINITY),
        }
    }
}

/// An `f64` of a sweep whose inputs are the cell's values scaled so that
/// their magnitudes sum to less than 2 (to within the rounding of that sum,
/// which the margin below absorbs). Every quantity the sweep compares
/// is then a polynomial whose terms, taken positive, sum to at most 2^11
/// (the largest, `qb^2 - 4 qa qc`: `|qb| <= 32`, `|qa| <= 32`, `|qc| <= 8`,
/// as `|h| < 2` and `|h' - h| < 4`; `value_at` is at most 512, the fraction
/// comparisons at most 256). With at most [`MAX_ROUNDINGS`] factors `1 +
/// δ` per term (an input's residual is one), its rounding error is below
/// `γ_16 2^11 < 2^-37`, plus what underflow adds, in the products or where
/// scaling made an input subnormal (far below 2^-1000). The bound is
/// absolute, so it holds however far apart the values are (no span limit
/// as in the integer sweeps). So a comparison whose two sides differ by more
/// than [`UNIT_DOUBT`] = 2^-32 has the exact sign; closer ones are in
/// doubt, and the cell goes to the exact sweeps. Unlike [`Filtered`], no
/// bound is carried along: the check is one subtraction per comparison.
#[derive(Clone, Copy, Debug)]
pub(super) struct Unit(pub(super) f64);

/// How far apart two [`Unit`] values must be for their order to be sure.
pub(super) const UNIT_DOUBT: f64 = 1.0 / (1u64 << 32) as f64;

impl Add for Unit {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Unit(self.0 + o.0)
    }
}

impl Sub for Unit {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Unit(self.0 - o.0)
    }
}

impl Mul for Unit {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Unit(self.0 * o.0)
    }
}

impl Neg for Unit {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Unit(-self.0)
    }
}

impl Num for Unit {
    type Bool = Maybe;
    type Doubt = Doubt;
    const ZERO: Self = Unit(0.0);
    const ONE: Self = Unit(1.0);
    const TWO: Self = Unit(2.0);
    const FOUR: Self = Unit(4.0);

    #[inline(always)]
    fn below(self, o: Self, or_equal: bool) -> Maybe {
        Maybe {
            value: (self.0 < o.0) | (or_equal & (self.0 == o.0)),
            sure: (self.0 - o.0).abs() > UNIT_DOUBT,
        }
    }

    /// A choice in doubt gives NaN, which every comparison it enters
    /// leaves in doubt, unless both candidates came out as the same number:
    /// then that number is the computed value of the right one, whose bound
    /// holds. (Equal fractions such as two ranges that both start at
    /// `t = 0` are common, and their order is never sure here.)
    #[inline(always)]
    fn select(c: Maybe, x: Self, y: Self) -> Self {
        let chosen = select_unpredictable(c.value, x, y);
        Unit(select_unpredictable(
            c.sure | (x.0 == y.0),
            chosen.0,
            f64::NAN,
        ))
    }

    /// Sure: scaling kept every input's sign (see [`unit_joins`](super::unit_joins)), and a
    /// residual never changes one (`|r| < |g|`, and `r = 0` when `g = 0`).
    #[inline(always)]
    fn input_in(self, closed: bool) -> Maybe {
        Maybe {
            value: is_in(self.0, closed),
            sure: true,
        }
    }
}

/// A sign of [`Filtered`] values that was in doubt: the sweep must be
/// redone exactly.
#[derive(Debug)]
pub(super) struct Doubt;

/// A truth value that may be in doubt (`sure` false). Combined as in
/// Kleene's three-valued logic, so that a sure `false` settles an `&` (and a
/// sure `true` an `|`) whatever the other side.
#[derive(Clone, Copy, Debug)]
pub(super) struct Maybe {
    value: bool,
    sure: bool,
}

impl BitAnd for Maybe {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        let settled = |x: Maybe| x.sure & !x.value;
        Maybe {
            value: self.value & o.value,
            sure: (self.sure & o.sure) | settled(self) | settled(o),
        }
    }
}

impl BitOr for Maybe {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        let settled = |x: Maybe| x.sure & x.value;
        Maybe {
            value: self.value | o.value,
            sure: (self.sure & o.sure) | settled(self) | settled(o),
        }
    }
}

impl Not for Maybe {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        Maybe {
            value: !self.value,
            sure: self.sure,
        }
    }
}

impl Logic for Maybe {
    type Doubt = Doubt;
    fn decided(self) -> Result<bool, Doubt> {
        if self.sure {
            Ok(self.value)
        } else {
            Err(Doubt)
        }
    }
}

/// Is `v` in the region: `v > 0` (open, the inside), or `v >= 0` (closed,
/// the outside given as `h = -g`)?
#[inline(always)]
pub(super) fn is_in<T: Num>(v: T, closed: bool) -> T::Bool {
    T::ZERO.below(v, closed)
}
