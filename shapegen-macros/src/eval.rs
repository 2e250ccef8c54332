//! Evaluating number expressions at compile time, for checks and exact constants.

use syn::{BinOp, Expr, Lit, UnOp};

/// The value of `e` as a real number, if it is built from number literals
/// with `+ - * /`, unary minus, parentheses and array-free arithmetic.
/// Division is real division (`1 / 3` is one third).
pub fn number(e: &Expr) -> Option<f64> {
    match e {
        Expr::Lit(l) => match &l.lit {
            Lit::Float(f) => f.base10_parse().ok(),
            Lit::Int(i) => i.base10_parse::<f64>().ok(),
            _ => None,
        },
        Expr::Paren(p) => number(&p.expr),
        Expr::Group(g) => number(&g.expr),
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => number(&u.expr).map(|x| -x),
        Expr::Binary(b) => {
            let (l, r) = (number(&b.left)?, number(&b.right)?);
            match b.op {
                BinOp::Add(_) => Some(l + r),
                BinOp::Sub(_) => Some(l - r),
                BinOp::Mul(_) => Some(l * r),
                BinOp::Div(_) => Some(l / r),
                _ => None,
            }
        }
        _ => None,
    }
}

/// The value of `e` if it is a whole, non-negative number built from literals
/// (`100`, `10 * 10`); `None` otherwise.
pub fn integer(e: &Expr) -> Option<usize> {
    let x = number(e)?;
    (x >= 0.0 && x.fract() == 0.0 && x <= usize::MAX as f64).then_some(x as usize)
}

/// The components of a vector argument: `[a, b, c]`, `[x; n]` or a scalar
/// broadcast to `n` components. `None` if it is none of these.
pub fn components(e: &Expr, n: usize) -> Option<Vec<Expr>> {
    match e {
        // The caller checks the length.
        Expr::Array(a) => Some(a.elems.iter().cloned().collect()),
        Expr::Repeat(r) => Some(vec![(*r.expr).clone(); n]),
        Expr::Paren(p) => components(&p.expr, n),
        Expr::Group(g) => components(&g.expr, n),
        _ if number(e).is_some() => Some(vec![e.clone(); n]),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(s: &str) -> Option<f64> {
        number(&syn::parse_str(s).unwrap())
    }

    #[test]
    fn arithmetic_on_literals() {
        assert_eq!(eval("1.0 / 3.0"), Some(1.0 / 3.0));
        assert_eq!(eval("1 / 3"), Some(1.0 / 3.0));
        assert_eq!(eval("-(2 * 0.5) + 3"), Some(2.0));
        assert_eq!(eval("0.2 * 22.0"), Some(0.2 * 22.0));
        assert_eq!(eval("X / 2.0"), None);
        assert_eq!(eval("f(1)"), None);
    }

    #[test]
    fn vector_arguments() {
        let n = |s: &str| components(&syn::parse_str(s).unwrap(), 3).map(|v| v.len());
        assert_eq!(n("[1.0, 2.0, 3.0]"), Some(3));
        assert_eq!(n("[0.6; 3]"), Some(3));
        assert_eq!(n("0.5"), Some(3));
        assert_eq!(n("[1.0, 2.0]"), Some(2));
        assert_eq!(n("ORIGIN"), None);
    }
}
