//! Formulas of `x`, `y`, `z`, `t` and named parameters, parsed once and evaluated many
//! times (nodal values, loads, level sets).
//!
//! Entry points: [`Formula::parse`], [`Formula::eval`], and [`Scalar`] (a constant or a
//! formula, as case files give values).
//!
//! ```
//! use fissure::formula::Formula;
//! use std::collections::BTreeMap;
//! let params = BTreeMap::from([("sigma".to_string(), 100.0)]);
//! let f = Formula::parse("sigma * (1 - y^2) + 1.5e-3 * t", &params).unwrap();
//! assert_eq!(f.eval([0.0, 0.5, 0.0], 1.0), 100.0 * 0.75 + 0.0015);
//! assert!(Formula::parse("sigma * (1 - y", &params).unwrap_err().to_string().contains("never closed"));
//! ```
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
    /// 1-based character position of the problem in the formula, when known.
    pub position: Option<usize>,
}

impl fmt::Display for FormulaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position {
            Some(p) => write!(f, "formula \"{}\": {} at character {p}", self.formula, self.message),
            None => write!(f, "formula \"{}\": {}", self.formula, self.message),
        }
    }
}

/// Functions the formulas may call (exmex's defaults for floats).
pub const FUNCTIONS: [&str; 24] = [
    "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "floor", "ceil",
    "round", "abs", "sqrt", "ln", "log", "log2", "log10", "exp", "signum", "cbrt",
];

/// A token of the pre-check.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tok {
    Operand,
    Function,
    Op(char),
    Open,
    Close,
}

/// Prefix given to parameter names in the text handed to exmex, so that a parameter never
/// reads as one of exmex's constants (`E`, `PI`, `π`): parameters win over constants.
const PARAM_PREFIX: &str = "fissure_param_";

/// Catches the common mistakes with a clear message and the 1-based character position
/// before exmex sees the text (its own messages are not meant for users), and returns the
/// text for exmex with numbers in scientific notation (`1.5e-3`, which exmex does not read)
/// written out in decimal and the names of `params` prefixed with [`PARAM_PREFIX`].
fn precheck(src: &str, params: &BTreeMap<String, f64>) -> Result<String, (String, usize)> {
    let chars: Vec<char> = src.chars().collect();
    let mut toks: Vec<(Tok, usize)> = vec![];
    let mut out = String::with_capacity(src.len());
    let mut open: Vec<usize> = vec![];
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let pos = i + 1;
        if c.is_whitespace() {
            out.push(c);
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '.') {
                // exponent sign: 1e-3
                if (chars[i] == 'e' || chars[i] == 'E')
                    && i + 1 < chars.len()
                    && (chars[i + 1] == '-' || chars[i + 1] == '+')
                {
                    i += 1;
                }
                i += 1;
            }
            let lit: String = chars[start..i].iter().collect();
            match lit.parse::<f64>() {
                Ok(v) if lit.contains(['e', 'E']) => out.push_str(&decimal(v)),
                Ok(_) => out.push_str(&lit),
                Err(_) => return Err((format!("'{lit}' is not a number"), pos)),
            }
            toks.push((Tok::Operand, pos));
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let name: String = chars[start..i].iter().collect();
            let mut j = i;
            while j < chars.len() && chars[j].is_whitespace() {
                j += 1;
            }
            let call = j < chars.len() && chars[j] == '(';
            if !call && params.contains_key(&name) {
                out.push_str(PARAM_PREFIX);
            }
            out.push_str(&name);
            if call {
                if !FUNCTIONS.contains(&name.as_str()) {
                    return Err((format!("unknown function '{name}' (known: {})", FUNCTIONS.join(", ")), pos));
                }
                toks.push((Tok::Function, pos));
            } else {
                toks.push((Tok::Operand, pos));
            }
            continue;
        }
        match c {
            '+' | '-' | '*' | '/' | '^' => toks.push((Tok::Op(c), pos)),
            '(' => {
                open.push(pos);
                toks.push((Tok::Open, pos));
            }
            ')' => {
                if open.pop().is_none() {
                    return Err(("')' without a matching '('".into(), pos));
                }
                toks.push((Tok::Close, pos));
            }
            _ => return Err((format!("unexpected character '{c}'"), pos)),
        }
        out.push(c);
        i += 1;
    }
    if let Some(&p) = open.last() {
        return Err(("'(' is never closed".into(), p));
    }
    for w in 0..toks.len() {
        let (t, p) = toks[w];
        let prev = if w > 0 { Some(toks[w - 1].0) } else { None };
        match t {
            Tok::Op(c) if matches!(c, '*' | '/' | '^') => match prev {
                None | Some(Tok::Open) => return Err((format!("'{c}' has no left operand"), p)),
                Some(Tok::Op(o)) => return Err((format!("'{c}' right after '{o}'"), p)),
                _ => {}
            },
            Tok::Operand | Tok::Function | Tok::Open => {
                if matches!(prev, Some(Tok::Operand) | Some(Tok::Close)) {
                    return Err(("missing operator".into(), p));
                }
            }
            Tok::Close => {
                if matches!(prev, Some(Tok::Open)) {
                    return Err(("empty parentheses".into(), p));
                }
                if let Some(Tok::Op(o)) = prev {
                    return Err((format!("'{o}' has no right operand"), p));
                }
            }
            _ => {}
        }
    }
    if let Some(&(Tok::Op(o), p)) = toks.last() {
        return Err((format!("'{o}' has no right operand"), p));
    }
    Ok(out)
}

/// A number in plain decimal notation (exmex reads no exponents).
fn decimal(v: f64) -> String {
    // `{}` on f64 never uses an exponent and round-trips exactly.
    format!("{v}")
}

/// exmex's message without the internal dumps some of them carry.
fn clean_message(m: &str) -> String {
    let cut = m.find(" Operator {").or_else(|| m.find("Operator {")).unwrap_or(m.len());
    m[..cut].trim_end_matches([',', ' ']).to_string()
}

impl std::error::Error for FormulaError {}

impl Formula {
    /// Parses `source`; its variables must be `x`, `y`, `z`, `t` or keys of `params`.
    /// `PI` (or `π`) and `E` are π and e, unless `params` has a key of that name: a
    /// parameter always wins over a constant.
    pub fn parse(source: &str, params: &BTreeMap<String, f64>) -> Result<Formula, FormulaError> {
        let err = |message: String| FormulaError { formula: source.to_string(), message, position: None };
        if source.trim().is_empty() {
            return Err(err("the formula is empty".into()));
        }
        let text = precheck(source, params).map_err(|(message, p)| FormulaError {
            formula: source.to_string(),
            message,
            position: Some(p),
        })?;
        let expr = exmex::parse::<f64>(&text).map_err(|e| err(clean_message(e.msg())))?;
        let mut slots = vec![];
        for name in expr.var_names() {
            let slot = match name.as_str() {
                "x" => Slot::X,
                "y" => Slot::Y,
                "z" => Slot::Z,
                "t" => Slot::T,
                other => match other.strip_prefix(PARAM_PREFIX).and_then(|p| params.get(p)) {
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
        self.expr.eval(&vars[..self.slots.len()]).map_err(|e| FormulaError {
            formula: self.source.clone(),
            message: clean_message(e.msg()),
            position: None,
        })
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
    /// A value of time `t` (dynamics): never ramped, a number is constant in time and a
    /// formula is evaluated at the time as it is ([`Scalar::of_time`]).
    OfTime(Box<Scalar>),
}

impl Scalar {
    #[inline]
    pub fn eval(&self, p: [f64; 3], t: f64) -> f64 {
        match self {
            Scalar::Const(c) => *c,
            Scalar::Formula(f) => f.eval(p, t),
            Scalar::OfTime(s) => s.eval(p, t),
        }
    }
    /// The same value read as a function of time: [`Scalar::eval_load`] no longer ramps it
    /// (a number stays constant, a formula is taken as it is).
    pub fn of_time(self) -> Scalar {
        match self {
            s @ Scalar::OfTime(_) => s,
            s => Scalar::OfTime(Box::new(s)),
        }
    }
    /// Value of a load at load factor `t`: a value that does not depend on `t` is
    /// scaled by `t` (linear ramp); a formula that uses `t` is taken as it is; a value of
    /// time ([`Scalar::OfTime`]) is never ramped.
    #[inline]
    pub fn eval_load(&self, p: [f64; 3], t: f64) -> f64 {
        match self {
            Scalar::Const(c) => c * t,
            Scalar::OfTime(s) => s.eval(p, t),
            Scalar::Formula(f) if f.depends_on_t() => f.eval(p, t),
            Scalar::Formula(f) => t * f.eval(p, t),
        }
    }
    pub fn is_zero(&self) -> bool {
        match self {
            Scalar::Const(c) => *c == 0.0,
            Scalar::OfTime(s) => s.is_zero(),
            Scalar::Formula(_) => false,
        }
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
    fn syntax_errors_name_the_position() {
        let p = BTreeMap::new();
        for (src, what, pos) in [
            ("y - 0.5 +* x", "'*' right after '+'", 10),
            ("y + sinn(x)", "unknown function 'sinn'", 5),
            ("(y - 0.5", "'(' is never closed", 1),
            ("y - 0.5)", "')' without a matching '('", 8),
            ("2 x", "missing operator", 3),
            ("x # 2", "unexpected character '#'", 3),
            ("x +", "'+' has no right operand", 3),
            ("sin()", "empty parentheses", 5),
        ] {
            let e = Formula::parse(src, &p).unwrap_err();
            assert!(e.message.contains(what) && e.position == Some(pos), "{src}: {e}");
            assert!(e.to_string().contains(&format!("at character {pos}")));
        }
        let f = Formula::parse("1.5e-3*x^2 + sqrt(abs(y)) - exp(-z) + 2E+1", &p).unwrap();
        let v = 1.5e-3 * 4.0 + 3.0 - (-1.0f64).exp() + 20.0;
        assert!((f.eval([2.0, -9.0, 1.0], 0.0) - v).abs() < 1e-14);
    }

    /// Issue 11 item 4: a parameter named like an exmex constant (`E`, `PI`) was read as
    /// e or π (a load of 1e7 became 2.718). Reference: the parameter's own value, exactly.
    #[test]
    fn parameters_named_like_constants_win_over_the_constants() {
        let p = BTreeMap::from([("E".to_string(), 1e7), ("PI".to_string(), 3.0), ("Emod".to_string(), 5.0)]);
        assert_eq!(Formula::parse("E", &p).unwrap().eval([0.0; 3], 0.0), 1e7);
        assert_eq!(Formula::parse("2*E*x + PI", &p).unwrap().eval([1.0, 0.0, 0.0], 0.0), 2e7 + 3.0);
        assert_eq!(Formula::parse("Emod - E/1e7", &p).unwrap().eval([0.0; 3], 0.0), 4.0);
        // Without such parameters the constants keep their meaning.
        let none = BTreeMap::new();
        assert_eq!(Formula::parse("E", &none).unwrap().eval([0.0; 3], 0.0), std::f64::consts::E);
        assert_eq!(Formula::parse("PI*x", &none).unwrap().eval([2.0, 0.0, 0.0], 0.0), 2.0 * std::f64::consts::PI);
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
