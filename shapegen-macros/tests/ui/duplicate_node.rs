shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A { slots { next: A = 0.5 } |s| { child!(next, s); } }
    node A { |s| {} }
}
fn main() {}
