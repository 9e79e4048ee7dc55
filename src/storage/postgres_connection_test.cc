#include "storage/postgres_connection.h"

#include <gtest/gtest.h>

#include "memloop/errors.h"
#include "memloop/fleet.h"

namespace memloop {
namespace {

TEST(PostgresDialectTest, NumbersParametersAsSqliteDoes) {
  EXPECT_EQ(ToPostgresDialect("SELECT a FROM t WHERE b=? AND c=?"),
            "SELECT a FROM t WHERE b=$1 AND c=$2");
  // ?1 names the first again; a later ? takes the number after the largest so far.
  EXPECT_EQ(ToPostgresDialect("DELETE FROM links WHERE to_id=? OR from_id=?1"),
            "DELETE FROM links WHERE to_id=$1 OR from_id=$1");
  EXPECT_EQ(ToPostgresDialect("UPDATE t SET a=? WHERE b=? AND c=?1 AND d=?"),
            "UPDATE t SET a=$1 WHERE b=$2 AND c=$1 AND d=$3");
  EXPECT_EQ(ToPostgresDialect("SELECT '?' FROM t WHERE a=?"), "SELECT '?' FROM t WHERE a=$1");
}

TEST(PostgresDialectTest, InsertOrReplaceUpdatesTheRowOfTheRobotAndFirstColumn) {
  EXPECT_EQ(ToPostgresDialect("INSERT OR REPLACE INTO info(key, value) VALUES(?,?)"),
            "INSERT INTO info(key, value) VALUES($1,$2) ON CONFLICT (robot, key) DO UPDATE SET "
            "value=EXCLUDED.value");
  EXPECT_EQ(ToPostgresDialect("INSERT OR REPLACE INTO images(image, session, name, stamp) "
                              "VALUES(?,?,?,?)"),
            "INSERT INTO images(image, session, name, stamp) VALUES($1,$2,$3,$4) ON CONFLICT "
            "(robot, image) DO UPDATE SET session=EXCLUDED.session, name=EXCLUDED.name, "
            "stamp=EXCLUDED.stamp");
}

TEST(PostgresDialectTest, InsertOrIgnoreAndLastRowId) {
  EXPECT_EQ(ToPostgresDialect("INSERT OR IGNORE INTO links(from_id, to_id, type) VALUES(?,?,?)"),
            "INSERT INTO links(from_id, to_id, type) VALUES($1,$2,$3) ON CONFLICT DO NOTHING");
  EXPECT_EQ(ToPostgresDialect("INSERT INTO p(loop, a) VALUES(last_insert_rowid(),?)"),
            "INSERT INTO p(loop, a) VALUES(lastval(),$1)");
  EXPECT_EQ(ToPostgresDialect("SELECT last_insert_rowid()"), "SELECT lastval()");
}

TEST(PostgresUriTest, APasswordIsNeverShown) {
  EXPECT_EQ(WithoutPassword("postgresql://r1:secret@host/db"), "postgresql://r1@host/db");
  EXPECT_EQ(WithoutPassword("postgres://r1:s3@host:5433/db?sslmode=require"),
            "postgres://r1@host:5433/db?sslmode=require");
  EXPECT_EQ(WithoutPassword("postgresql://host/db?user=r1&password=secret"),
            "postgresql://host/db?user=r1&password=...");
  EXPECT_EQ(WithoutPassword("postgresql://r1@host/db"), "postgresql://r1@host/db");
}

TEST(PostgresUriTest, AnErrorNamingAServerMapShowsNoPassword) {
  EXPECT_STREQ(DatabaseError("postgresql://r1:secret@host/db", "gone").what(),
               "postgresql://r1@host/db: gone");
  EXPECT_EQ(DatabaseError("postgresql://h/db?password=secret", "gone").path(),
            "postgresql://h/db?password=...");
  EXPECT_STREQ(InputError("/maps/a:b@c.db", "gone").what(), "/maps/a:b@c.db: gone");  // a file
}

TEST(PostgresUriTest, TheRobotIsTheUriUser) {
  EXPECT_EQ(RobotMapUri("postgresql://host/db", "r1"), "postgresql://host/db?user=r1");
  EXPECT_EQ(RobotMapUri("postgresql:///db?host=/run/pg", "robot 2"),
            "postgresql:///db?host=/run/pg&user=robot%202");
  EXPECT_EQ(RobotMapUri("postgresql://r1:pw@host/db", "r1"), "postgresql://r1:pw@host/db");
  EXPECT_EQ(RobotMapUri("postgresql://r1@host/db", ""), "postgresql://r1@host/db");
  try {
    RobotMapUri("postgresql://r2:pw@host/db", "r1");
    ADD_FAILURE() << "a URI of another robot was accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "postgresql://r2@host/db: connects as r2, not as the robot r1 that --robot names");
  }
  EXPECT_THROW(RobotMapUri("map.db", "r1"), InputError);
}

}  // namespace
}  // namespace memloop
