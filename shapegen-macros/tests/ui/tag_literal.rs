shapegen::generator! {
    struct G;
    start: S;
    node S {
        tags { "trunk" }
        |s| {}
    }
}
fn main() {}
