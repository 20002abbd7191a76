fn main() {
    let s = caymos::generate::tangency();
    print!("{}", caymos::generate::to_toml(&s));
}
