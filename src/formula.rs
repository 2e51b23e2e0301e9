//! Formulas of `x`, `y`, `z`, `t` and named parameters, parsed once and evaluated many
//! times (nodal values, loads, level sets).
//!
//! Entry points: [`Formula::parse`], [`Formula::eval`], and [`Scalar`] (a constant or a
//! formula, as case files give values).
//!
//! Parsing and evaluation are done by the `exmex` crate. `t` is the load factor of the
//! current step (pseudo-time, from 0 to 1 over a ramp). Parameters are fixed when the
//! formula is parsed. Interpreted formulas are ~50× slower than native code: evaluate
//! them once per node or face and keep the values.

use exmex::prelude::*;
use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;

/// Largest number of distinct variables one formula may use.
const MAX_VARS: usize = 32;

/// Where a formula variable takes its value from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Slot {
    X,
    Y,
    Z,
    T,
    Param(f64),
}

/// A parsed formula. The compiled expression is shared (`Arc`): an exmex expression is
/// about 20 KB, and a formula given once in a case file is attached to many nodes.
#[derive(Clone)]
pub struct Formula {
    source: String,
    expr: Arc<FlatEx<f64>>,
    slots: Vec<Slot>,
}

impl fmt::Debug for Formula {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Formula({:?})", self.source)
    }
}

/// A formula that failed to parse or to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct FormulaError {
    pub formula: String,
    pub message: String,
}

impl fmt::Display for FormulaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "formula \"{}\": {}", self.formula, self.message)
    }
}

impl std::error::Error for FormulaError {}

impl Formula {
    /// Parses `source`; its variables must be `x`, `y`, `z`, `t` or keys of `params`.
    pub fn parse(source: &str, params: &BTreeMap<String, f64>) -> Result<Formula, FormulaError> {
        let err = |message: String| FormulaError { formula: source.to_string(), message };
        if source.trim().is_empty() {
            return Err(err("the formula is empty".into()));
        }
        let expr = exmex::parse::<f64>(source).map_err(|e| err(e.msg().to_string()))?;
        let mut slots = vec![];
        for name in expr.var_names() {
            let slot = match name.as_str() {
                "x" => Slot::X,
                "y" => Slot::Y,
                "z" => Slot::Z,
                "t" => Slot::T,
                other => match params.get(other) {
                    Some(v) => Slot::Param(*v),
                    None => {
                        let known: Vec<&str> = params.keys().map(|s| s.as_str()).collect();
                        return Err(err(format!(
                            "unknown variable '{other}' (use x, y, z, t{}{})",
                            if known.is_empty() { "" } else { " or a parameter: " },
                            known.join(", ")
                        )));
                    }
                },
            };
            slots.push(slot);
        }
        if slots.len() > MAX_VARS {
            return Err(err(format!("more than {MAX_VARS} variables")));
        }
        let f = Formula { source: source.to_string(), expr: Arc::new(expr), slots };
        // Evaluate once at the origin to catch errors early (not the value: 1/x is fine).
        f.eval_checked([0.1234, 0.2345, 0.3456], 0.5).map(|_| f).map_err(|e| err(e.message))
    }

    /// The text of the formula as written.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Whether the formula depends on `t`.
    pub fn depends_on_t(&self) -> bool {
        self.slots.contains(&Slot::T)
    }

    /// Evaluates at point `p` and load factor `t`; errors (not NaN) are reported.
    pub fn eval_checked(&self, p: [f64; 3], t: f64) -> Result<f64, FormulaError> {
        let mut vars = [0.0; MAX_VARS];
        for (v, s) in vars.iter_mut().zip(&self.slots) {
            *v = match s {
                Slot::X => p[0],
                Slot::Y => p[1],
                Slot::Z => p[2],
                Slot::T => t,
                Slot::Param(c) => *c,
            };
        }
        self.expr
            .eval(&vars[..self.slots.len()])
            .map_err(|e| FormulaError { formula: self.source.clone(), message: e.msg().to_string() })
    }

    /// Evaluates at point `p` and load factor `t`; an evaluation error gives NaN.
    #[inline]
    pub fn eval(&self, p: [f64; 3], t: f64) -> f64 {
        self.eval_checked(p, t).unwrap_or(f64::NAN)
    }
}

/// A scalar value given in a case file: a number, or a formula of x, y, z, t.
#[derive(Debug, Clone)]
pub enum Scalar {
    Const(f64),
    Formula(Formula),
}

impl Scalar {
    #[inline]
    pub fn eval(&self, p: [f64; 3], t: f64) -> f64 {
        match self {
            Scalar::Const(c) => *c,
            Scalar::Formula(f) => f.eval(p, t),
        }
    }
    /// Value of a load at load factor `t`: a value that does not depend on `t` is
    /// scaled by `t` (linear ramp); a formula that uses `t` is taken as it is.
    #[inline]
    pub fn eval_load(&self, p: [f64; 3], t: f64) -> f64 {
        match self {
            Scalar::Const(c) => c * t,
            Scalar::Formula(f) if f.depends_on_t() => f.eval(p, t),
            Scalar::Formula(f) => t * f.eval(p, t),
        }
    }
    pub fn is_zero(&self) -> bool {
        matches!(self, Scalar::Const(c) if *c == 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluates_coordinates_and_parameters() {
        let mut p = BTreeMap::new();
        p.insert("a".to_string(), 2.0);
        let f = Formula::parse("a*x + y^2 - z + t", &p).unwrap();
        assert!((f.eval([1.0, 3.0, 4.0], 0.5) - (2.0 + 9.0 - 4.0 + 0.5)).abs() < 1e-14);
        let g = Formula::parse("sqrt(x^2+y^2) - 1", &p).unwrap();
        assert!((g.eval([3.0, 4.0, 0.0], 0.0) - 4.0).abs() < 1e-14);
    }

    #[test]
    fn unknown_variable_and_syntax_errors_are_reported() {
        let p = BTreeMap::new();
        let e = Formula::parse("x + b", &p).unwrap_err();
        assert!(e.to_string().contains("unknown variable 'b'"), "{e}");
        assert!(Formula::parse("x + * 2", &p).is_err());
        assert!(Formula::parse("  ", &p).is_err());
    }
}
